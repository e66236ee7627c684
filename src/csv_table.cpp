// The CSV tokenizer behind the measurement readers (csv_table.h).
#include "csv_table.h"

#include <cerrno>
#include <cstdlib>
#include <sstream>

#include "caliper/errors.h"

namespace caliper::detail {

namespace {

std::string trim_blanks(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return {};
  return s.substr(a, s.find_last_not_of(" \t\r\n") - a + 1);
}

// How many times `c` occurs outside double quotes.
int count_unquoted(const std::string& line, char c) {
  int n = 0;
  bool quoted = false;
  for (char ch : line) {
    if (ch == '"') quoted = !quoted;
    else if (ch == c && !quoted) ++n;
  }
  return n;
}

char detect_separator(const std::string& first_line) {
  if (count_unquoted(first_line, ';') > 0) return ';';
  if (count_unquoted(first_line, ',') > 0) return ',';
  if (count_unquoted(first_line, '\t') > 0) return '\t';
  return ',';
}

std::vector<std::string> split_line(const std::string& line, char sep, const std::string& where) {
  std::vector<std::string> cells;
  std::string cell;
  bool quoted = false, was_quoted = false;
  auto finish = [&] {
    cells.push_back(was_quoted ? cell : trim_blanks(cell));
    cell.clear();
    was_quoted = false;
  };
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c != '"') cell += c;
      else if (i + 1 < line.size() && line[i + 1] == '"') cell += line[++i];  // "" is one quote
      else quoted = false;
    } else if (c == '"' && trim_blanks(cell).empty()) {
      cell.clear();
      quoted = was_quoted = true;
    } else if (c == sep) {
      finish();
    } else if (!(was_quoted && (c == ' ' || c == '\t' || c == '\r'))) {
      if (was_quoted) throw Error(ErrorKind::Format, where + ": text after a closing quote", "csv");
      cell += c;
    }
  }
  if (quoted) throw Error(ErrorKind::Format, where + ": a quote is opened and not closed", "csv");
  finish();
  return cells;
}

}  // namespace

CsvText split_csv(const std::string& text, const std::string& source) {
  CsvText out;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  bool separator_known = false;
  while (std::getline(in, line)) {
    ++number;
    if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line = line.substr(3);
    const std::string t = trim_blanks(line);
    if (t.empty() || t[0] == '#') continue;
    if (!separator_known) {
      out.separator = detect_separator(line);
      separator_known = true;
    }
    out.lines.push_back({number, split_line(line, out.separator, source + ", line " + std::to_string(number))});
  }
  return out;
}

std::optional<double> parse_decimal(const std::string& cell) {
  std::string t = trim_blanks(cell);
  if (t.empty()) return std::nullopt;
  const size_t comma = t.find(',');
  if (comma != std::string::npos) {
    if (t.find(',', comma + 1) != std::string::npos || t.find('.') != std::string::npos) return std::nullopt;
    t[comma] = '.';
  }
  // strtod in the "C" locale (the library never changes it); the whole cell must be the number.
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || errno == ERANGE) return std::nullopt;
  return v;
}

std::string lower_case(std::string text) {
  for (auto& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

}  // namespace caliper::detail
