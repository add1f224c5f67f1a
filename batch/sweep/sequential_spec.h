// A sweep spec's `sequential:` (docs/sweeps.md, "Sequential paired testing"): the opt-in
// sequential paired test's level, its block of episodes between looks, the pair kinds it tests
// and the label pairs it compares. Read strictly, as the rest of the spec.
#pragma once

#include "batch/report/sequential_pairs.h"
#include "batch/sweep/sweep_spec.h"
#include "configs/yaml_reader.h"

namespace tavis::batch::sweep {

// `spec` is read up to its policies (the label pairs must name its labels). Throws
// configs::ConfigError naming the key and the value.
report::SequentialSettings ReadSequential(const configs::YamlValue& node, const SweepSpec& spec);

}  // namespace tavis::batch::sweep
