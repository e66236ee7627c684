// A small CPU rasterizer that turns a mesh into a PNG picture (docs, previews, the CLI), on a
// machine with no GPU and no display. Smooth per-vertex-normal Blinn-Phong shading under a key
// light, a fill light and a sky/ground ambient; a soft contact shadow and a fading grid on the
// floor; 3×3 supersampling; a light-grey background gradient.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "caliper/body/mesh.h"

namespace caliper {

// Where the camera stands, in the body frame (+Y up, the body faces +Z, +X = the body's left).
enum class View {
  Front,         // from +Z: the body's face; its left (+X) is on the image's right
  Side,          // from +X: the body's left side; the body faces the image's left
  Back,          // from −Z: the body's back; its left is on the image's left
  ThreeQuarter,  // from +X+Z at 45°: front and left side; the body faces the image's left-front
  Top,           // from above (+Y, leaning 15° toward +Z): the body's front at the image's bottom,
                 // its left on the image's right (the back of a T-posed hand, the top of the head)
};
const char* to_string(View view);

struct RenderOptions {
  int width = 600;   // pixels, per view (render_views_png puts views side by side)
  int height = 900;  // pixels
  View view = View::Front;
  std::array<float, 3> body_rgb{0.80f, 0.78f, 0.75f};  // sRGB in [0, 1]
  bool floor_grid = true;      // floor with grid lines and a soft contact shadow
  bool orthographic = false;   // false: perspective camera with a 30° vertical field of view
  // Optional per-vertex value (N entries, or empty) coloured as a heat map from blue (low) to
  // red (high), replacing body_rgb. The range is [scalar_min, scalar_max] unless they are
  // equal, then the values' own minimum and maximum.
  std::vector<float> vertex_scalar;
  float scalar_min = 0.0f;
  float scalar_max = 0.0f;
  // Optional UV layout (uv_coordinates U×2 and uv_faces, one row per face; both empty = none):
  // the body is painted with a checker texture of `checker_squares` squares along each side of
  // the unit UV square instead of body_rgb, to show a layout's seams and stretch.
  UvCoordinates uv_coordinates;
  Faces uv_faces;
  int checker_squares = 40;
  // Close-up: with focus_radius > 0 (metres) every view frames the sphere of that radius around
  // focus_center (body frame, metres) instead of the whole mesh; the rest of the body runs out
  // of the picture. 0 = frame the whole mesh.
  std::array<double, 3> focus_center{0.0, 0.0, 0.0};
  double focus_radius = 0.0;
};

// PNG bytes (8-bit RGB) of `vertices` (N×3, metres) and `faces` (F×3, indices into vertices),
// framed to fit with a margin, camera looking at mid-body with a slight downward tilt. The
// floor is drawn at the mesh's lowest point (y = 0 for avatars). Throws Error(InvalidArgument)
// for an empty mesh, non-finite vertices, out-of-range face indices, bad sizes or colours, or a
// vertex_scalar of the wrong length or with non-finite values, or a negative or non-finite
// focus_radius / non-finite focus_center.
std::string render_png(const Vertices& vertices, const Faces& faces, const RenderOptions& options = {});

// Several views side by side in one PNG (views.size()·width × height), all at the same scale,
// so lengths compare across panels. options.view is ignored.
std::string render_views_png(const Vertices& vertices, const Faces& faces, const std::vector<View>& views,
                             const RenderOptions& options = {});

// PNG bytes of a width×height 8-bit RGB image, rows top to bottom (width·height·3 bytes).
std::string encode_png_rgb8(int width, int height, const std::vector<std::uint8_t>& rgb);

}  // namespace caliper
