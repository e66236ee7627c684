// What the avatar writers (glTF, VRM, FBX) share: the skin influences they write (each vertex's
// 4 largest weights, what engines keep, renormalised) and writing a file.
#pragma once
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "caliper/errors.h"

namespace caliper::export_detail {

// The 4 largest weights of one vertex (ties broken by the lower joint index, so the output is
// deterministic), as float weights whose left-to-right float sum is exactly 1.
struct Influences {
  std::array<int, 4> joints{0, 0, 0, 0};
  std::array<float, 4> weights{0, 0, 0, 0};
};

inline float float_sum(const std::array<float, 4>& w) { return ((w[0] + w[1]) + w[2]) + w[3]; }

inline Influences top_influences(const Eigen::SparseMatrix<double, Eigen::RowMajor>& skin, Eigen::Index vertex) {
  // A fixed four-slot insertion: this runs for every written vertex, and a heap vector and a
  // sort per vertex were an eighth of the .glb writer's time (docs/performance.md).
  auto before = [](const std::pair<double, int>& a, const std::pair<double, int>& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  };
  std::array<std::pair<double, int>, 4> best{};
  size_t count = 0;
  for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(skin, vertex); it; ++it) {
    if (!(it.value() > 0)) continue;
    const std::pair<double, int> candidate{it.value(), static_cast<int>(it.col())};
    if (count == best.size() && !before(candidate, best.back())) continue;
    size_t k = count < best.size() ? count++ : best.size() - 1;
    for (; k > 0 && before(candidate, best[k - 1]); --k) best[k] = best[k - 1];
    best[k] = candidate;
  }
  const std::span<const std::pair<double, int>> all(best.data(), count);
  Influences out;
  if (all.empty()) {  // BodyModel rejects this; keep the vertex bound to the root anyway
    out.weights[0] = 1.0f;
    return out;
  }
  double kept = 0;
  for (const auto& [w, j] : all) kept += w;
  for (size_t k = 0; k < all.size(); ++k) {
    out.joints[k] = all[k].second;
    out.weights[k] = static_cast<float>(all[k].first / kept);
  }
  // Put the rounding residue on the largest weight, then nudge it by ulps until the float sum is
  // exactly 1 (the validator and engines check the sum; a few ulps off is a warning in some).
  out.weights[0] = 1.0f - ((out.weights[1] + out.weights[2]) + out.weights[3]);
  for (int step = 0; step < 16 && float_sum(out.weights) != 1.0f; ++step)
    out.weights[0] = std::nextafter(out.weights[0], float_sum(out.weights) < 1.0f ? 2.0f : 0.0f);
  return out;
}

inline void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) throw Error(ErrorKind::Io, "cannot open '" + path + "' for writing", path);
  file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  file.close();
  if (!file) throw Error(ErrorKind::Io, "cannot write '" + path + "'", path);
}

}  // namespace caliper::export_detail
