#include "batch/report/pooled_cells.h"

#include <map>
#include <tuple>

#include "scenarios/split.h"

namespace tavis::batch::report {

std::vector<PooledCell> PoolBySetting(const std::vector<CellEpisodes>& cells) {
  using Key = std::tuple<std::string, std::string, std::string, CameraProtocol>;
  std::vector<PooledCell> pooled;
  std::map<Key, std::size_t> index;
  for (const CellEpisodes& cell : cells) {
    const Key key{cell.config.task, cell.config.robot, scenarios::ToString(cell.config.split), cell.config.camera};
    auto found = index.find(key);
    if (found == index.end()) {
      found = index.emplace(key, pooled.size()).first;
      pooled.push_back({std::get<0>(key), std::get<1>(key), std::get<2>(key), std::get<3>(key), {}});
    }
    std::vector<cell::EpisodeRecord>& episodes = pooled[found->second].episodes;
    episodes.insert(episodes.end(), cell.episodes.begin(), cell.episodes.end());
  }
  return pooled;
}

}  // namespace tavis::batch::report
