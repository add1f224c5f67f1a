// What tavis prints for an error naming settings (tools/error_text.h): the flag a user typed,
// the cell table's own where it is not the key with dashes; any other error as it is.
#include "tools/error_text.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "batch/output/setting_error.h"

namespace tavis::tools {
namespace {

TEST(ErrorText, SettingsAreNamedByTheirFlags) {
  EXPECT_EQ(FlagOfSetting("max_attempts"), "--max-attempts");
  EXPECT_EQ(FlagOfSetting("observation_keys"), "--keys") << "the cell table's flag";
  EXPECT_EQ(FlagOfSetting("episode_start"), "--episode");
  EXPECT_EQ(ErrorText(batch::output::SettingError("video_size", "must be even, got 63x48")),
            "--video-size must be even, got 63x48");
  EXPECT_EQ(ErrorText(batch::output::SettingsAdvice<std::runtime_error>(
                batch::output::SettingKey("resume") + " with a larger " + batch::output::SettingKey("max_attempts"))),
            "--resume with a larger --max-attempts");
  EXPECT_EQ(ErrorText(std::runtime_error("resume_x: as it is")), "resume_x: as it is");
}

TEST(ErrorText, ACommandsErrorsKeepTheirTypeAndNameFlags) {
  EXPECT_THROW(RunNamingFlags([] { throw batch::output::SettingError("shard", "must be I/N"); }),
               std::invalid_argument);
  try {
    RunNamingFlags(
        [] { throw batch::output::SettingsAdvice<std::runtime_error>(batch::output::SettingKey("resume")); });
    FAIL() << "nothing thrown";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "--resume");
  }
  try {
    RunNamingFlags([] { throw std::out_of_range("untouched"); });
    FAIL() << "nothing thrown";
  } catch (const std::out_of_range& error) {
    EXPECT_STREQ(error.what(), "untouched") << "an error naming no setting passes as it was";
  }
}

}  // namespace
}  // namespace tavis::tools
