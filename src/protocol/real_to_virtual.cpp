// Real → virtual linear maps (paper §3.3, Fig. 7).
#include "caliper/protocol/real_to_virtual.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "caliper/errors.h"
#include "gate.h"
#include "caliper/vocabulary/catalogue.h"
#include "json_read.h"

namespace caliper {

namespace {
const LinearMap kIdentity{};

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorKind::Io, "cannot open '" + path + "'", path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string canonical(const std::string& name, const std::string& where) {
  const MeasurementInfo* info = find_measurement_info(name);
  if (!info) throw Error(ErrorKind::Format, where + ": unknown measurement '" + name + "'", name);
  return info->name;
}
}  // namespace

const LinearMap& RealToVirtual::map(const std::string& measurement) const {
  auto it = maps_.find(measurement);
  return it == maps_.end() ? kIdentity : it->second;
}

void RealToVirtual::set(const std::string& measurement, LinearMap m) {
  if (!std::isfinite(m.slope) || !std::isfinite(m.offset) || m.slope <= 0)
    throw Error(ErrorKind::InvalidArgument, "map for " + measurement + " needs a finite positive slope", measurement);
  maps_[canonical(measurement, "real-to-virtual map")] = m;
}

void RealToVirtual::apply(std::map<std::string, double>& values) const {
  for (auto& [name, v] : values) v = map(name).apply(v);
}

RealToVirtual RealToVirtual::from_json(const std::string& text) {
  return gate("real-to-virtual map", "maps", [&] { return read_json(text); });
}

RealToVirtual RealToVirtual::read_json(const std::string& text) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    throw Error(ErrorKind::Format, std::string("real-to-virtual map: not valid JSON: ") + e.what(), "maps");
  }
  using namespace detail;
  const JsonPlace doc{"real-to-virtual map", ""};
  if (json_string_or(j, "format", "", doc) != "caliper-real-to-virtual")
    throw Error(ErrorKind::Format, "real-to-virtual map: expected \"format\": \"caliper-real-to-virtual\"", "format");
  const nlohmann::json& maps = json_require(j, "maps", doc);
  if (!maps.is_object()) (doc / "maps").fail("must be an object of measurement: {slope, offset_cm, pairs, rmse_cm}");
  RealToVirtual r;
  for (const auto& [name, m] : maps.items()) {
    const JsonPlace at = doc / "maps" / name;
    LinearMap lm;
    lm.slope = json_number(json_require(m, "slope", at), at / "slope");
    lm.offset = json_number_or(m, "offset_cm", 0.0, at) / 100.0;
    lm.pairs = static_cast<int>(json_integer_or(m, "pairs", 0, at, 0, std::numeric_limits<int>::max()));
    lm.rmse = json_number_or(m, "rmse_cm", 0.0, at) / 100.0;
    r.set(name, lm);
  }
  return r;
}

std::string RealToVirtual::to_json() const {
  nlohmann::json j = {{"format", "caliper-real-to-virtual"}, {"version", 1}, {"maps", nlohmann::json::object()}};
  for (const auto& [name, m] : maps_)
    j["maps"][name] = {{"slope", m.slope}, {"offset_cm", m.offset * 100}, {"pairs", m.pairs}, {"rmse_cm", m.rmse * 100}};
  return j.dump(2) + "\n";
}

RealToVirtual RealToVirtual::load(const std::string& path) { return from_json(read_file(path)); }

void RealToVirtual::save(const std::string& path) const {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw Error(ErrorKind::Io, "cannot write '" + path + "'", path);
  out << to_json();
  if (!out) throw Error(ErrorKind::Io, "failed writing '" + path + "'", path);
}

RealToVirtual RealToVirtual::fit_csv(const std::string& path) {
  return gate("'" + path + "'", "pairs", [&] { return read_pairs_csv(path); });
}

RealToVirtual RealToVirtual::read_pairs_csv(const std::string& path) {
  std::istringstream in(read_file(path));
  std::string line;
  std::map<std::string, std::vector<std::pair<double, double>>> pairs;
  int line_no = 0;
  bool header_seen = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) cells.push_back(cell);
    if (!header_seen) {
      header_seen = true;
      if (cells.size() != 3 || cells[0] != "measurement" || cells[1] != "real_cm" || cells[2] != "virtual_cm")
        throw Error(ErrorKind::Format, path + ":1: expected the header measurement,real_cm,virtual_cm", "header");
      continue;
    }
    if (cells.size() != 3)
      throw Error(ErrorKind::Format, path + ":" + std::to_string(line_no) + ": expected 3 fields", "line " + std::to_string(line_no));
    double real = 0, virt = 0;
    try {
      size_t a = 0, b = 0;
      real = std::stod(cells[1], &a);
      virt = std::stod(cells[2], &b);
      if (a != cells[1].size() || b != cells[2].size()) throw std::invalid_argument("trailing");
    } catch (const std::exception&) {
      throw Error(ErrorKind::Format, path + ":" + std::to_string(line_no) + ": real_cm and virtual_cm must be numbers",
                  "line " + std::to_string(line_no));
    }
    if (!std::isfinite(real) || !std::isfinite(virt) || real <= 0 || virt <= 0 || real > 300 || virt > 300)
      throw Error(ErrorKind::OutOfRange, path + ":" + std::to_string(line_no) + ": values must be in (0, 300] cm",
                  "line " + std::to_string(line_no));
    pairs[canonical(cells[0], path + ":" + std::to_string(line_no))].push_back({real / 100, virt / 100});
  }
  RealToVirtual r;
  for (const auto& [name, ps] : pairs) {
    const double n = static_cast<double>(ps.size());
    if (ps.size() < 3)
      throw Error(ErrorKind::Format, "fitting " + name + " needs at least 3 pairs, got " + std::to_string(ps.size()), name);
    double mx = 0, my = 0;
    for (auto [x, y] : ps) { mx += x / n; my += y / n; }
    double sxx = 0, sxy = 0;
    for (auto [x, y] : ps) { sxx += (x - mx) * (x - mx); sxy += (x - mx) * (y - my); }
    if (sxx <= 1e-12) throw Error(ErrorKind::Format, "fitting " + name + ": all real values are equal", name);
    LinearMap m;
    m.slope = sxy / sxx;
    m.offset = my - m.slope * mx;
    m.pairs = static_cast<int>(ps.size());
    double ss = 0;
    for (auto [x, y] : ps) ss += (m.apply(x) - y) * (m.apply(x) - y);
    m.rmse = std::sqrt(ss / n);
    if (m.slope <= 0) throw Error(ErrorKind::Format, "fitting " + name + ": the pairs give a non-positive slope", name);
    r.maps_[name] = m;
  }
  if (r.maps_.empty()) throw Error(ErrorKind::Format, path + ": no pairs", path);
  return r;
}

}  // namespace caliper
