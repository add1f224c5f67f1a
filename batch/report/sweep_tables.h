// The sweep's tables in the paper's layout, written from summary.json (SweepSummaryJson) as
// Markdown, CSV and LaTeX: per suite the success rates with 95% Wilson intervals and suite means;
// id - ood differences; head vs fixed on matched episodes with McNemar's exact test; the length
// of successful episodes; GALT per robot, task and split in the validation table's layout.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tavis::batch::report {

struct TextTable {
  std::string name;  // file stem: tables/<name>.md, .csv, .tex
  std::string title;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::string note;  // below the table (Markdown, LaTeX); empty for none
};

std::vector<TextTable> SweepTables(const nlohmann::ordered_json& summary);

std::string ToMarkdown(const TextTable& table);
std::string ToCsv(const TextTable& table);    // RFC 4180 quoting; the note is not part of the CSV
std::string ToLatex(const TextTable& table);  // a booktabs tabular in a table float

// How the tables print numbers (the HTML report uses the same): a fraction in percent with one
// decimal ("45.8"), an interval "[31.2, 61.0]", a difference of fractions in points with its sign
// ("-12.5"), seconds with two decimals, a p-value with three
// significant digits.
std::string Percent(double fraction);
std::string PercentInterval(double low, double high);
std::string Points(double difference);
std::string Seconds(const nlohmann::ordered_json& value);  // "-" for null
std::string PValue(double p);

}  // namespace tavis::batch::report
