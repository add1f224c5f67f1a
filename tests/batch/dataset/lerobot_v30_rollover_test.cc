// v3.0 files roll over at the size limits: with tiny limits every episode starts a new data file
// and a new mp4 per camera, and LeRobot's readers still see one dataset.
#include <gtest/gtest.h>

#include <string>

#include "tests/batch/dataset/known_dataset_expectations.h"
#include "tests/batch/dataset/node_parquet.h"

namespace tavis::batch::dataset {
namespace {

using namespace testing;  // NOLINT: the test support's many helpers

TEST(LeRobotV30Rollover, EveryEpisodeStartsNewFilesThatStillReadAsOneDataset) {
  const std::string scratch = ScratchDir();
  const std::string root = scratch + "/dataset";
  KnownDataset known = MakeKnownDataset(DatasetVersion::kV30);
  known.layout.data_files_size_mb = 1e-6;
  known.layout.video_files_size_mb = 1e-6;
  WriteKnownDataset(known, root);
  const DatasetView view = LoadDataset(root);

  ASSERT_EQ(view.data_files.size(), 3u);
  const nlohmann::json& rows = view.episodes_table["hyparquet"]["rows"];
  ASSERT_EQ(rows.size(), 3u);
  for (std::size_t e = 0; e < rows.size(); ++e) {
    EXPECT_EQ(view.data_files[e], root + "/data/chunk-000/file-00" + std::to_string(e) + ".parquet");
    EXPECT_EQ(Int(rows[e]["data/chunk_index"]), 0);
    EXPECT_EQ(Int(rows[e]["data/file_index"]), static_cast<int64_t>(e));
    for (const std::string& key : view.video_keys) {
      EXPECT_EQ(Int(rows[e]["videos/" + key + "/file_index"]), static_cast<int64_t>(e)) << key;
      EXPECT_EQ(rows[e]["videos/" + key + "/from_timestamp"].get<double>(), 0.0)
          << key << " episode " << e << " starts its file";
    }
  }
  EXPECT_EQ(view.info["data_files_size_in_mb"].get<double>(), 1e-6);
  ExpectDataRowsAsLeRobotReadsThem(view);
  ExpectRowsHoldKnownValues(view, known);
  ExpectLookedUpFramesAreKnown(ExpectVideosAsLeRobotReadsThem(view, scratch), known);

  // LeRobot reads the data files as one table, in sorted-path order.
  const nlohmann::json indices = QueryWithDuckdb("SELECT \"index\" FROM read_parquet('" + root + "/data/*/*.parquet')");
  ASSERT_EQ(indices.size(), 24u);
  for (std::size_t i = 0; i < indices.size(); ++i) EXPECT_EQ(Int(indices[i]["index"]), static_cast<int64_t>(i));
}

}  // namespace
}  // namespace tavis::batch::dataset
