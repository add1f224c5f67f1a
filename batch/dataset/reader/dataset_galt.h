// GALT of every episode of a LeRobot dataset, from its commanded actions: what `tavis galt
// --dataset` prints per episode and what a sweep's Figure 4 takes as a dataset reference, computed
// by this one function so that the two agree.
#pragma once

#include <filesystem>
#include <vector>

#include "batch/dataset/reader/dataset_actions.h"
#include "kinematics/galt.h"

namespace tavis::batch::dataset::reader {

struct DatasetGalt {
  DatasetActions actions;
  double fps = 0.0;                               // the rate GALT ran at
  std::vector<kinematics::TrajectoryView> views;  // one per episode, into actions' values
  std::vector<kinematics::GaltResult> results;    // one per episode, in episode order
};

// GALT of every episode of `actions` sampled at `fps` (the dataset's info.json fps unless a caller
// overrides it). The views point into the returned actions.
DatasetGalt ComputeDatasetGalt(DatasetActions actions, double fps);

// The detected GALT values (s) of a dataset at its own rate (meta/info.json's fps): the galt_s
// of the episodes whose reason is ok or ok_post_anchor, in episode order. Throws
// std::runtime_error naming the file when the dataset cannot be read (ReadDatasetActions).
std::vector<double> DatasetGaltSeconds(const std::filesystem::path& dataset_dir);

}  // namespace tavis::batch::dataset::reader
