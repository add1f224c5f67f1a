// An enum's name table (kinematics/enum_names.h): both directions read the one table, a value it
// lacks gets the caller's fallback, and the list of names keeps the table's order.
#include "kinematics/enum_names.h"

#include <gtest/gtest.h>

#include <string>

namespace tavis::kinematics {
namespace {

enum class Colour { kRed, kDarkGreen, kBlue };

constexpr EnumName<Colour> kColours[] = {{Colour::kRed, "red"}, {Colour::kDarkGreen, "dark-green"}};

TEST(EnumNames, NameAndValueComeFromTheSameEntry) {
  EXPECT_STREQ(NameOf(kColours, Colour::kDarkGreen, "?"), "dark-green");
  ASSERT_NE(FindNamed(kColours, "dark-green"), nullptr);
  EXPECT_EQ(FindNamed(kColours, "dark-green")->value, Colour::kDarkGreen);
  EXPECT_EQ(FindNamed(kColours, "red")->value, Colour::kRed);
}

TEST(EnumNames, WhatTheTableLacksIsNotFound) {
  EXPECT_STREQ(NameOf(kColours, Colour::kBlue, "unknown"), "unknown");
  EXPECT_EQ(FindNamed(kColours, "blue"), nullptr);
  EXPECT_EQ(FindNamed(kColours, "Red"), nullptr) << "names are matched exactly";
  EXPECT_EQ(FindNamed(kColours, ""), nullptr);
}

TEST(EnumNames, TheListKeepsTheTablesOrder) { EXPECT_EQ(NameList(kColours), "red, dark-green"); }

}  // namespace
}  // namespace tavis::kinematics
