// Errors that name settings (batch/output/setting_error.h): the library names each by its key, a
// command by the name its user gave it, from the same exception.
#include "batch/output/setting_error.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace tavis::batch::output {
namespace {

std::string AsFlag(const std::string& key) { return "--" + key + "!"; }

TEST(SettingError, NamesTheKeyOrWhatTheCommandCallsIt) {
  const SettingError error("videos", "must be at least 0, got -1");
  EXPECT_STREQ(error.what(), "videos must be at least 0, got -1");
  EXPECT_EQ(error.MessageNaming(AsFlag), "--videos! must be at least 0, got -1");
}

TEST(SettingsAdvice, NamesEveryMarkedKeyAndLeavesTheRestAsItIs) {
  const std::string text = "/tmp/{a}/cell holds results; give " + SettingKey("overwrite") + " or " +
                           SettingKey("resume") + " (not " + SettingKey("resume") + "_x)";
  const SettingsAdvice<std::invalid_argument> advice(text);
  EXPECT_STREQ(advice.what(), "/tmp/{a}/cell holds results; give overwrite or resume (not resume_x)");
  EXPECT_EQ(advice.MessageNaming(AsFlag),
            "/tmp/{a}/cell holds results; give --overwrite! or --resume! (not --resume!_x)");
  EXPECT_EQ(NameSettings("no settings here", AsFlag), "no settings here");
  // What it derives from is the caller's choice: a refusal or a run that could not finish.
  const SettingsAdvice<std::runtime_error> ran_out("more " + SettingKey("max_attempts"));
  EXPECT_STREQ(static_cast<const std::runtime_error&>(ran_out).what(), "more max_attempts");
}

}  // namespace
}  // namespace tavis::batch::output
