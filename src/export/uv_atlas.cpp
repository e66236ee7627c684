// A picture of a UV layout (include/caliper/export/uv_atlas.h): triangles filled by scanning
// pixel centres against edge functions, edges drawn as 1-pixel lines by stepping along their
// longer axis. Triangles whose UVs run clockwise (flipped) are filled red, so a fold shows.
#include "caliper/export/uv_atlas.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "caliper/errors.h"
#include "caliper/export/render.h"

namespace caliper {

std::string render_uv_atlas_png(const UvCoordinates& uv, const Faces& uv_faces, const UvAtlasOptions& options) {
  const int n = options.size;
  if (n < 16 || n > 8192) throw Error(ErrorKind::InvalidArgument, "atlas size must be in [16, 8192] pixels", "size");
  if (!uv.allFinite()) throw Error(ErrorKind::InvalidArgument, "UV coordinates contain NaN or infinity", "uv_coordinates");
  if (uv_faces.rows() > 0 && (uv_faces.minCoeff() < 0 || uv_faces.maxCoeff() >= uv.rows()))
    throw Error(ErrorKind::InvalidArgument, "UV face index out of range", "uv_faces");
  std::vector<std::uint8_t> rgb(static_cast<size_t>(n) * static_cast<size_t>(n) * 3, 255);
  auto put = [&](int x, int y, std::array<std::uint8_t, 3> c) {
    if (x < 0 || y < 0 || x >= n || y >= n) return;
    const size_t at = (static_cast<size_t>(y) * static_cast<size_t>(n) + static_cast<size_t>(x)) * 3;
    rgb[at] = c[0], rgb[at + 1] = c[1], rgb[at + 2] = c[2];
  };
  // Pixel coordinates: x = u·n, y = (1 − v)·n (row 0 is v = 1).
  auto pixel = [&](Eigen::Index i) { return Eigen::Vector2d(uv(i, 0) * n, (1 - uv(i, 1)) * n); };
  // The unit square's border, light blue.
  for (int k = 0; k < n; ++k) {
    put(k, 0, {170, 200, 230}), put(k, n - 1, {170, 200, 230});
    put(0, k, {170, 200, 230}), put(n - 1, k, {170, 200, 230});
  }
  if (options.fill) {
    for (Eigen::Index f = 0; f < uv_faces.rows(); ++f) {
      const Eigen::Vector2d a = pixel(uv_faces(f, 0)), b = pixel(uv_faces(f, 1)), c = pixel(uv_faces(f, 2));
      // In pixel space y points down, so a counter-clockwise UV triangle has a negative cross.
      const double cross = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
      if (cross == 0) continue;
      const std::array<std::uint8_t, 3> colour = cross < 0 ? std::array<std::uint8_t, 3>{222, 222, 222}
                                                           : std::array<std::uint8_t, 3>{240, 120, 120};
      const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
      const int x1 = std::min(n - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}))));
      const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
      const int y1 = std::min(n - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
      auto edge = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
        return (q - p).x() * (r - p).y() - (q - p).y() * (r - p).x();
      };
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const Eigen::Vector2d p(x + 0.5, y + 0.5);
          const double w0 = edge(b, c, p), w1 = edge(c, a, p), w2 = edge(a, b, p);
          const bool inside = cross < 0 ? (w0 <= 0 && w1 <= 0 && w2 <= 0) : (w0 >= 0 && w1 >= 0 && w2 >= 0);
          if (inside) put(x, y, colour);
        }
    }
  }
  auto line = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
    const double steps = std::max(1.0, std::ceil(std::max(std::abs(q.x() - p.x()), std::abs(q.y() - p.y()))));
    for (int s = 0; s <= static_cast<int>(steps); ++s) {
      const Eigen::Vector2d r = p + (q - p) * (s / steps);
      put(static_cast<int>(std::floor(r.x())), static_cast<int>(std::floor(r.y())), {60, 60, 70});
    }
  };
  for (Eigen::Index f = 0; f < uv_faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) line(pixel(uv_faces(f, k)), pixel(uv_faces(f, (k + 1) % 3)));
  return encode_png_rgb8(n, n, rgb);
}

}  // namespace caliper
