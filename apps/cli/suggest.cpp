// Suggestions after a refused command line: a misspelt option, a value typed as people write it.
#include <algorithm>
#include <iostream>
#include <regex>

#include "common.h"

namespace caliper::cli {

namespace {

// Edits (insert, delete, substitute, swap two neighbours) from a to b: "heigth" is one from "height".
std::string detail_lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

int typing_distance(const std::string& a, const std::string& b) {
  const size_t n = a.size(), m = b.size();
  std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1));
  for (size_t i = 0; i <= n; ++i) d[i][0] = static_cast<int>(i);
  for (size_t j = 0; j <= m; ++j) d[0][j] = static_cast<int>(j);
  for (size_t i = 1; i <= n; ++i)
    for (size_t j = 1; j <= m; ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1])});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[n][m];
}

// The subcommand the command line reached (`model info`, `avatar`), or the app itself.
const CLI::App* reached_command(const CLI::App& app, int argc, char** argv) {
  const CLI::App* at = &app;
  for (int i = 1; i < argc; ++i) {
    if (argv[i][0] == '-') break;
    const CLI::App* next = nullptr;
    for (const CLI::App* sub : at->get_subcommands([](const CLI::App*) { return true; }))
      if (sub->get_name() == argv[i]) next = sub;
    if (!next) break;
    at = next;
  }
  return at;
}

std::vector<std::string> long_option_names(const CLI::App& command) {
  std::vector<std::string> names;
  for (const CLI::Option* o : command.get_options())
    for (const std::string& l : o->get_lnames()) names.push_back("--" + l);
  return names;
}

}  // namespace

std::string value_hint(const std::string& text) {
  static const std::regex with_unit(R"(^\s*[0-9]+([.,][0-9]+)?\s*(cm|mm|m|in|inch|inches|ft|kg|g|lb|lbs)\s*$)",
                                    std::regex::icase);
  static const std::regex decimal_comma(R"(^\s*[0-9]+,[0-9]+\s*$)");
  std::smatch m;
  if (std::regex_match(text, m, with_unit))
    return "'" + text + "': write the number alone; lengths are in centimetres and weight in kilograms (e.g. 165, not " +
           "165cm), so a value in inches or pounds has to be converted first";
  if (std::regex_match(text, decimal_comma)) {
    std::string dotted = text;
    std::replace(dotted.begin(), dotted.end(), ',', '.');
    return "'" + text + "': use a dot for decimals: " + dotted;
  }
  return "";
}

std::vector<std::string> closest_names(const std::string& word, const std::vector<std::string>& names) {
  std::vector<std::pair<int, std::string>> scored;
  for (const std::string& n : names) {
    const int d = typing_distance(word, n);
    // A slip of up to a third of the word, or a part of the name ("chest" in chest_circumference).
    if (d <= std::max<int>(1, static_cast<int>(word.size()) / 3)) scored.push_back({d, n});
    else if (word.size() >= 3 && n.find(word) != std::string::npos) scored.push_back({100 + static_cast<int>(n.size()), n});
  }
  std::stable_sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::string> out;
  for (const auto& [d, n] : scored) out.push_back(n);
  return out;
}

std::string unknown_measurement_message(const std::string& name, const std::string& option) {
  std::vector<std::string> names;
  for (const MeasurementInfo& info : measurement_catalogue()) {
    names.push_back(info.name);
    for (const std::string& a : info.aliases) names.push_back(a);
  }
  std::string msg = option + ": unknown measurement '" + name + "'";
  const auto near = closest_names(detail_lower(name), names);
  if (!near.empty()) {
    msg += "; did you mean ";
    for (size_t i = 0; i < near.size() && i < 4; ++i) msg += (i ? ", " : "") + near[i];
    msg += "?";
  }
  msg += " The accepted names:";
  for (const MeasurementInfo& info : measurement_catalogue()) msg += " " + info.name;
  return msg + " (also their aliases, e.g. height, arm_span, inseam, hip_width; `caliper model info` lists what a model measures)";
}

void explain_parse_error(const CLI::App& app, int argc, char** argv) {
  const CLI::App* command = reached_command(app, argc, argv);
  const std::vector<std::string> options = long_option_names(*command);
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg.rfind("--", 0) == 0) {
      const std::string name = arg.substr(0, arg.find('='));
      if (std::find(options.begin(), options.end(), name) != options.end()) continue;
      const auto near = closest_names(name, options);
      if (!near.empty()) std::cerr << "caliper: unknown option " << name << ": did you mean " << near.front() << "?\n";
      continue;
    }
    if (const std::string hint = value_hint(arg); !hint.empty()) std::cerr << "caliper: " << hint << "\n";
  }
}

}  // namespace caliper::cli
