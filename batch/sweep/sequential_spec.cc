#include "batch/sweep/sequential_spec.h"

#include <algorithm>
#include <string>

#include "batch/sweep/spec_lists.h"

namespace tavis::batch::sweep {
namespace {

using configs::YamlValue;

std::string LabelList(const SweepSpec& spec) {
  std::string labels;
  for (const PolicySpec& policy : spec.policies) labels += (labels.empty() ? "" : ", ") + policy.label;
  return labels;
}

std::string ReadLabel(const YamlValue& value, const SweepSpec& spec) {
  const std::string name = value.AsString();
  const bool known = std::any_of(spec.policies.begin(), spec.policies.end(),
                                 [&name](const PolicySpec& policy) { return policy.label == name; });
  if (!known) value.Fail("no policy has the label '" + name + "' (labels: " + LabelList(spec) + ")");
  return name;
}

}  // namespace

report::SequentialSettings ReadSequential(const YamlValue& node, const SweepSpec& spec) {
  RejectUnknownKeys(node, {"alpha", "block", "pairs", "policies"});
  report::SequentialSettings settings;
  settings.enabled = true;
  if (const auto alpha = node.Optional("alpha"))
    settings.test.alpha = alpha->AsDouble({0.0, 0.5, true, "", " (the chance of a wrong decision)"});
  if (const auto block = node.Optional("block")) settings.test.block = ReadCount(*block, 1, spec.episodes);
  if (const auto pairs = node.Optional("pairs")) {
    if (!pairs->IsSequence()) pairs->Fail("must be a list of cameras and perturbations, got " + pairs->Text());
    settings.cameras = settings.perturbations = false;
    for (const YamlValue& kind : pairs->Elements()) {
      const std::string name = kind.AsString();
      if (name != "cameras" && name != "perturbations")
        kind.Fail("unknown pair kind '" + name + "' (known: cameras, perturbations)");
      bool& chosen = name == "cameras" ? settings.cameras : settings.perturbations;
      if (chosen) kind.Fail(kind.Text() + " is listed twice");
      chosen = true;
    }
  }
  if (const auto policies = node.Optional("policies")) {
    if (!policies->IsSequence()) policies->Fail("must be a list of [LABEL, LABEL] pairs, got " + policies->Text());
    for (const YamlValue& pair : policies->Elements()) {
      const std::vector<YamlValue> labels = pair.IsSequence() ? pair.Elements() : std::vector<YamlValue>{};
      if (labels.size() != 2) pair.Fail("must name two labels, [FIRST, SECOND], got " + pair.Text());
      const std::pair<std::string, std::string> names{ReadLabel(labels[0], spec), ReadLabel(labels[1], spec)};
      if (names.first == names.second) pair.Fail("compares '" + names.first + "' with itself");
      for (const auto& [first, second] : settings.policies) {
        if ((first == names.first && second == names.second) || (first == names.second && second == names.first))
          pair.Fail(pair.Text() + " is listed twice");
      }
      settings.policies.push_back(names);
    }
  }
  node.ExpectNoOtherKeys();
  if (!settings.cameras && !settings.perturbations && settings.policies.empty())
    node.Fail("tests no pair: give pairs: [cameras, perturbations] (or some of them) or policies: [[A, B]]");
  return settings;
}

}  // namespace tavis::batch::sweep
