// Internal: untrusted CSV text as spreadsheets write it, split into cells. One tokenizer for the
// measurement-set and measurement-table readers (capture/measurement_set.h):
// - the separator is detected once per file, from its first line that is neither blank nor a
//   '#' comment: ';' if that line has one outside quotes (European spreadsheets, where the comma
//   is the decimal mark), else ',' if it has one, else a tab; a comma file's header never holds a
//   ';' outside quotes, so the choice is unambiguous;
// - cells may be quoted ("165,5"; "" inside quotes is one quote); a UTF-8 byte-order mark, CRLF
//   and a last line without newline are accepted; a quote left open at the end of a line is an
//   Error(Format) naming the line.
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace caliper::detail {

struct CsvLine {
  int number = 0;                  // 1-based line in the file
  std::vector<std::string> cells;  // blanks around each cell trimmed, quotes removed
};

struct CsvText {
  char separator = ',';
  std::vector<CsvLine> lines;  // blank and '#' comment lines left out
};

// `source` names the text in errors ("measurement set", a file path).
CsvText split_csv(const std::string& text, const std::string& source);

// A number as a spreadsheet writes it: "165.5", or "165,5" with a decimal comma (one comma, no
// dot: "1,655.0" and "1.655,0" are refused rather than guessed). nullopt if the cell is not a
// number (empty, text, trailing units such as "165cm").
std::optional<double> parse_decimal(const std::string& cell);

std::string lower_case(std::string text);

}  // namespace caliper::detail
