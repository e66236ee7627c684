// Software renderer and PNG writer: decode our own PNGs back (zlib, filter type 0) and check
// pixels of hand-built cubes and spheres.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "caliper/errors.h"
#include "caliper/export/render.h"
#include "caliper/export/uv_atlas.h"
#include "fixtures.h"

namespace caliper {
namespace {

using test::kind_of;

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  const std::uint8_t* at(int x, int y) const { return &rgb[(static_cast<size_t>(y) * width + x) * 3]; }
};

std::uint32_t be32(const std::string& s, size_t at) {
  return (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at])) << 24) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 1])) << 16) |
         (static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 2])) << 8) |
         static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 3]));
}

// A strict decoder for exactly what the writer promises: RGB8, no interlace, filter 0 rows,
// valid CRCs, IHDR first and IEND last.
Image decode(const std::string& png) {
  Image img;
  EXPECT_GE(png.size(), 8u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  size_t at = 8;
  std::string idat;
  bool seen_end = false;
  int chunk_index = 0;
  while (at + 12 <= png.size()) {
    const std::uint32_t len = be32(png, at);
    const std::string type = png.substr(at + 4, 4);
    const std::string data = png.substr(at + 8, len);
    const std::uint32_t crc = be32(png, at + 8 + len);
    uLong expect = crc32(0L, Z_NULL, 0);
    expect = crc32(expect, reinterpret_cast<const Bytef*>(png.data() + at + 4), 4 + len);
    EXPECT_EQ(crc, static_cast<std::uint32_t>(expect)) << "bad CRC in chunk " << type;
    if (chunk_index == 0) {
      EXPECT_EQ(type, "IHDR");
      EXPECT_EQ(len, 13u);
      img.width = static_cast<int>(be32(data, 0));
      img.height = static_cast<int>(be32(data, 4));
      EXPECT_EQ(data.substr(8, 5), std::string("\x08\x02\x00\x00\x00", 5));
    }
    if (type == "IDAT") idat += data;
    if (type == "IEND") { seen_end = true; at += 12 + len; break; }
    at += 12 + len;
    ++chunk_index;
  }
  EXPECT_TRUE(seen_end);
  EXPECT_EQ(at, png.size());
  const size_t row = static_cast<size_t>(img.width) * 3 + 1;
  std::vector<std::uint8_t> raw(row * static_cast<size_t>(img.height));
  uLongf raw_size = raw.size();
  EXPECT_EQ(uncompress(raw.data(), &raw_size, reinterpret_cast<const Bytef*>(idat.data()), idat.size()), Z_OK);
  EXPECT_EQ(raw_size, raw.size());
  img.rgb.reserve(raw.size());
  for (int y = 0; y < img.height; ++y) {
    EXPECT_EQ(raw[row * y], 0) << "row " << y << " is not filter type 0";
    img.rgb.insert(img.rgb.end(), raw.begin() + row * y + 1, raw.begin() + row * (y + 1));
  }
  return img;
}

// Axis-aligned box centred at `c` with half sizes h, faces wound counter-clockwise from outside.
Mesh centred_box(Eigen::Vector3d c, Eigen::Vector3d h) {
  Mesh m;
  m.vertices.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    m.vertices.row(i) << c.x() + ((i & 1) ? h.x() : -h.x()), c.y() + ((i & 2) ? h.y() : -h.y()),
        c.z() + ((i & 4) ? h.z() : -h.z());
  m.faces.resize(12, 3);
  m.faces << 0, 2, 3, 0, 3, 1,  // −Z
      4, 5, 7, 4, 7, 6,         // +Z
      0, 1, 5, 0, 5, 4,         // −Y
      2, 6, 7, 2, 7, 3,         // +Y
      0, 4, 6, 0, 6, 2,         // −X
      1, 3, 7, 1, 7, 5;         // +X
  return m;
}

Mesh uv_sphere(Eigen::Vector3d c, double r, int rings = 24, int segments = 48) {
  Mesh m;
  m.vertices.resize(2 + (rings - 1) * segments, 3);
  m.vertices.row(0) << c.x(), c.y() + r, c.z();
  m.vertices.row(1) << c.x(), c.y() - r, c.z();
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double th = std::numbers::pi * i / rings, ph = 2 * std::numbers::pi * j / segments;
      m.vertices.row(2 + (i - 1) * segments + j) << c.x() + r * std::sin(th) * std::sin(ph), c.y() + r * std::cos(th),
          c.z() + r * std::sin(th) * std::cos(ph);
    }
  std::vector<std::array<int, 3>> f;
  auto v = [&](int i, int j) { return 2 + (i - 1) * segments + (j % segments); };
  for (int j = 0; j < segments; ++j) {
    f.push_back({0, v(1, j), v(1, j + 1)});
    f.push_back({1, v(rings - 1, j + 1), v(rings - 1, j)});
    for (int i = 1; i < rings - 1; ++i) {
      f.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
      f.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  }
  m.faces.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (size_t k = 0; k < f.size(); ++k) m.faces.row(static_cast<Eigen::Index>(k)) << f[k][0], f[k][1], f[k][2];
  return m;
}

Mesh merge(const Mesh& a, const Mesh& b) {
  Mesh m;
  m.vertices.resize(a.vertices.rows() + b.vertices.rows(), 3);
  m.vertices << a.vertices, b.vertices;
  m.faces.resize(a.faces.rows() + b.faces.rows(), 3);
  m.faces << a.faces, (b.faces.array() + static_cast<std::int32_t>(a.vertices.rows())).matrix();
  return m;
}

bool is_grey(const std::uint8_t* p) {
  return std::abs(p[0] - p[1]) <= 6 && std::abs(p[1] - p[2]) <= 6 && p[0] > 120;
}
bool is_red(const std::uint8_t* p) { return p[0] > 60 && p[0] > 2 * p[1] && p[0] > 2 * p[2]; }

TEST(Png, SignatureAndHeaderCarryTheSize) {
  const Mesh cube = centred_box({0, 0.5, 0}, {0.5, 0.5, 0.5});
  RenderOptions o;
  o.width = 40;
  o.height = 70;
  const std::string png = render_png(cube.vertices, cube.faces, o);
  ASSERT_GE(png.size(), 33u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(be32(png, 16), 40u);
  EXPECT_EQ(be32(png, 20), 70u);
}

TEST(Png, EncodeRoundTripsExactBytes) {
  std::vector<std::uint8_t> rgb(5 * 3 * 3);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<std::uint8_t>(i * 37 + 11);
  const Image img = decode(encode_png_rgb8(5, 3, rgb));
  EXPECT_EQ(img.width, 5);
  EXPECT_EQ(img.height, 3);
  EXPECT_EQ(img.rgb, rgb);
  EXPECT_THROW(encode_png_rgb8(5, 3, std::vector<std::uint8_t>(10)), Error);
  EXPECT_THROW(encode_png_rgb8(0, 3, {}), Error);
}

TEST(Render, CubeCoversTheCentreAndLeavesCornersBackground) {
  const Mesh cube = centred_box({0, 0.5, 0}, {0.5, 0.5, 0.5});
  RenderOptions o;
  o.width = 120;
  o.height = 160;
  o.body_rgb = {0.9f, 0.15f, 0.1f};
  for (View view : {View::Front, View::Side, View::Back, View::ThreeQuarter, View::Top}) {
    o.view = view;
    const Image img = decode(render_png(cube.vertices, cube.faces, o));
    ASSERT_EQ(img.width, 120);
    ASSERT_EQ(img.height, 160);
    EXPECT_TRUE(is_red(img.at(60, 80))) << to_string(view);
    for (auto [x, y] : {std::pair{0, 0}, {119, 0}, {0, 159}, {119, 159}})
      EXPECT_TRUE(is_grey(img.at(x, y))) << to_string(view) << " corner " << x << "," << y;
  }
}

TEST(Render, DefaultBodyColourIsWarmOnACoolGreyBackground) {
  const Mesh cube = centred_box({0, 0.5, 0}, {0.5, 0.5, 0.5});
  RenderOptions o;
  o.width = 60;
  o.height = 90;
  const Image img = decode(render_png(cube.vertices, cube.faces, o));
  const std::uint8_t* centre = img.at(30, 45);
  EXPECT_GT(centre[0], centre[2] + 4);  // body (0.80, 0.78, 0.75) under a warm key light
  EXPECT_GE(centre[0], centre[1]);
  const std::uint8_t* corner = img.at(0, 0);
  EXPECT_GE(corner[2], corner[0]);  // background is neutral to slightly cool
}

TEST(Render, CheckerTextureFollowsTheUvs) {
  // The box's UVs project it along z: the front face fills one checker square, light (warm) or
  // dark (blue) depending on which square the UVs put it in.
  const Mesh cube = centred_box({0, 0.5, 0}, {0.5, 0.5, 0.5});
  RenderOptions o;
  o.width = 60;
  o.height = 90;
  o.uv_faces = cube.faces;
  const Eigen::Vector3d lo = cube.vertices.colwise().minCoeff(), hi = cube.vertices.colwise().maxCoeff();
  auto project = [&](double u0) {
    UvCoordinates uv(cube.vertices.rows(), 2);
    for (Eigen::Index i = 0; i < uv.rows(); ++i)
      uv.row(i) << u0 + 0.4 * (cube.vertices(i, 0) - lo.x()) / (hi.x() - lo.x()),
          0.4 * (cube.vertices(i, 1) - lo.y()) / (hi.y() - lo.y());
    return uv;
  };
  o.checker_squares = 2;
  o.uv_coordinates = project(0.05);  // square (0, 0): light
  const Image light = decode(render_png(cube.vertices, cube.faces, o));
  o.uv_coordinates = project(0.55);  // square (1, 0): dark
  const Image dark = decode(render_png(cube.vertices, cube.faces, o));
  EXPECT_GT(light.at(30, 45)[0], light.at(30, 45)[2]);
  EXPECT_GT(dark.at(30, 45)[2], dark.at(30, 45)[0]);
  EXPECT_GT(light.at(30, 45)[0], dark.at(30, 45)[0] + 60);
  o.uv_faces = Faces(cube.faces.topRows(3));
  EXPECT_THROW(render_png(cube.vertices, cube.faces, o), Error);
}

int red_pixels(const Image& img) {
  int n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) n += is_red(img.at(x, y));
  return n;
}

// Tiny grey anchors at fixed places hold the framing still while the sphere grows.
Mesh sphere_in_fixed_frame(double radius) {
  Mesh scene = uv_sphere({0, 0, 0}, radius);
  for (Eigen::Vector3d c : {Eigen::Vector3d(-1, -1, 0), Eigen::Vector3d(1, -1, 0), Eigen::Vector3d(-1, 1, 0),
                            Eigen::Vector3d(1, 1, 0)})
    scene = merge(scene, centred_box(c, {0.01, 0.01, 0.01}));
  return scene;
}

TEST(Render, SphereSilhouetteGrowsWithItsSquaredRadius) {
  RenderOptions o;
  o.width = 200;
  o.height = 200;
  o.body_rgb = {0.9f, 0.15f, 0.1f};
  o.orthographic = true;
  const Mesh small = sphere_in_fixed_frame(0.3), large = sphere_in_fixed_frame(0.5);
  const int a_small = red_pixels(decode(render_png(small.vertices, small.faces, o)));
  const int a_large = red_pixels(decode(render_png(large.vertices, large.faces, o)));
  ASSERT_GT(a_small, 500);
  // Orthographic: area ∝ r², so the ratio is (0.5 / 0.3)² ≈ 2.78 (pixel edges blur it a little).
  EXPECT_NEAR(static_cast<double>(a_large) / a_small, 25.0 / 9.0, 0.15);

  o.orthographic = false;  // perspective: still grows
  const int p_small = red_pixels(decode(render_png(small.vertices, small.faces, o)));
  const int p_large = red_pixels(decode(render_png(large.vertices, large.faces, o)));
  EXPECT_GT(p_large, 2 * p_small);
}

// Bounding box of the red pixels within columns [x0, x1).
std::array<int, 4> red_bounds(const Image& img, int x0, int x1) {
  std::array<int, 4> b{1 << 30, -1, 1 << 30, -1};
  for (int y = 0; y < img.height; ++y)
    for (int x = x0; x < x1; ++x)
      if (is_red(img.at(x, y))) {
        b[0] = std::min(b[0], x);
        b[1] = std::max(b[1], x);
        b[2] = std::min(b[2], y);
        b[3] = std::max(b[3], y);
      }
  return b;
}

// The top view looks down with the body's front at the image's bottom and its left (+X) on the
// image's right: a wide slab behind (−Z) and a narrow post on the left-front (+X, +Z), seen from
// above, put the slab's pixels in the upper half and the post right of the centre and low.
TEST(Render, TopViewLooksDownWithTheFrontAtTheBottom) {
  const Mesh slab = centred_box({0, 0.3, -0.4}, {0.6, 0.3, 0.1});
  const Mesh post = centred_box({0.4, 0.3, 0.4}, {0.1, 0.3, 0.1});
  Mesh both;
  both.vertices.resize(16, 3);
  both.vertices << slab.vertices, post.vertices;
  both.faces.resize(24, 3);
  both.faces << slab.faces, (post.faces.array() + 8).matrix();
  RenderOptions o;
  o.width = 160;
  o.height = 160;
  o.body_rgb = {0.9f, 0.15f, 0.1f};
  o.view = View::Top;
  const Image img = decode(render_png(both.vertices, both.faces, o));
  int upper = 0, lower = 0, lower_right = 0, lower_left = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (is_red(img.at(x, y))) {
        (y < img.height / 2 ? upper : lower) += 1;
        if (y >= img.height / 2) (x >= img.width / 2 ? lower_right : lower_left) += 1;
      }
  EXPECT_GT(upper, 2 * lower) << "the slab behind the body's centre is at the top";
  EXPECT_GT(lower_right, 4 * std::max(1, lower_left)) << "the post on the body's left-front is low and on the right";
}

TEST(Render, ViewsShareOneScale) {
  // A 2 × 1 × 0.5 m box: 2 m wide seen from the front, 0.5 m seen from the side, 1 m tall in both.
  const Mesh slab = centred_box({0, 0.5, 0}, {1.0, 0.5, 0.25});
  RenderOptions o;
  o.width = 200;
  o.height = 150;
  o.body_rgb = {0.9f, 0.15f, 0.1f};
  o.orthographic = true;
  const Image img = decode(render_views_png(slab.vertices, slab.faces, {View::Front, View::Side}, o));
  ASSERT_EQ(img.width, 400);
  ASSERT_EQ(img.height, 150);
  const auto front = red_bounds(img, 0, 200), side = red_bounds(img, 200, 400);
  ASSERT_GE(front[1], 0);
  ASSERT_GE(side[1], 0);
  const double front_w = front[1] - front[0] + 1, side_w = side[1] - side[0] + 1;
  // Widths are exact in orthographic views; framed one by one, the side panel would be zoomed
  // in on its narrow slab (ratio ≈ 3), framed together they keep the true ratio 4.
  EXPECT_NEAR(front_w / side_w, 4.0, 0.2);
  EXPECT_LT(front[1] - front[0], 200);  // the front panel is not cropped
}

// A close-up (focus_center, focus_radius) frames a small part of a large scene: a red "head" of
// radius 10 cm on top of a grey 1.6 m "body". Framed whole, the head is a few per cent of the
// picture; framed on it, it fills most of the picture, centred.
TEST(Render, FocusFramesTheGivenSphere) {
  const Eigen::Vector3d head_c(0, 1.7, 0);
  Mesh scene = merge(centred_box({0, 0.8, 0}, {0.2, 0.8, 0.12}), uv_sphere(head_c, 0.1));
  RenderOptions o;
  o.width = 200;
  o.height = 200;
  o.floor_grid = false;
  // Colour the sphere red through a per-vertex scalar: the box's 8 vertices low, the sphere's high.
  o.vertex_scalar.assign(static_cast<size_t>(scene.vertices.rows()), 1.0f);
  for (int i = 0; i < 8; ++i) o.vertex_scalar[static_cast<size_t>(i)] = 0.0f;
  o.scalar_min = 0.0f;
  o.scalar_max = 1.0f;
  for (bool ortho : {false, true}) {
    o.orthographic = ortho;
    o.focus_radius = 0;
    const int whole = red_pixels(decode(render_png(scene.vertices, scene.faces, o)));
    o.focus_center = {head_c.x(), head_c.y(), head_c.z()};
    o.focus_radius = 0.1;
    const Image close = decode(render_png(scene.vertices, scene.faces, o));
    const int near = red_pixels(close);
    EXPECT_LT(whole, 0.05 * 200 * 200) << (ortho ? "orthographic" : "perspective");
    // The sphere's disc fills kFill (0.86) of the frame's half-height: π·0.86²/4 ≈ 58 % of the square.
    EXPECT_GT(near, 0.45 * 200 * 200) << (ortho ? "orthographic" : "perspective");
    const auto b = red_bounds(close, 0, 200);
    EXPECT_NEAR(0.5 * (b[0] + b[1]), 99.5, 3);
    EXPECT_NEAR(0.5 * (b[2] + b[3]), 99.5, 3);
    EXPECT_LT(b[1] - b[0], 190);  // the whole sphere is in the frame
  }
}

TEST(Render, HeatMapRunsFromBlueToRed) {
  const Mesh cube = centred_box({0, 0.5, 0}, {0.5, 0.5, 0.5});
  RenderOptions o;
  o.width = 120;
  o.height = 120;
  for (Eigen::Index i = 0; i < cube.vertices.rows(); ++i) o.vertex_scalar.push_back(static_cast<float>(cube.vertices(i, 0)));
  const Image img = decode(render_png(cube.vertices, cube.faces, o));
  // From the front the body's left (+X, high values) is on the image's right.
  const std::uint8_t* left = img.at(40, 60);
  const std::uint8_t* right = img.at(80, 60);
  EXPECT_GT(left[2], left[0] + 30) << "low values should be blue";
  EXPECT_GT(right[0], right[2] + 30) << "high values should be red";
}

TEST(Render, SameInputGivesSameBytes) {
  const Mesh s = uv_sphere({0, 1, 0}, 0.5, 8, 12);
  RenderOptions o;
  o.width = 50;
  o.height = 50;
  EXPECT_EQ(render_png(s.vertices, s.faces, o), render_png(s.vertices, s.faces, o));
}

TEST(Render, BadInputThrowsNamingTheField) {
  const Mesh cube = centred_box({0, 0.5, 0}, {0.5, 0.5, 0.5});
  std::string field;
  EXPECT_EQ(kind_of([&] { render_png(Vertices(0, 3), cube.faces); }, nullptr, &field), ErrorKind::InvalidArgument);
  EXPECT_EQ(field, "vertices");
  EXPECT_EQ(kind_of([&] { render_png(cube.vertices, Faces(0, 3)); }, nullptr, &field), ErrorKind::InvalidArgument);
  EXPECT_EQ(field, "faces");

  Vertices nan = cube.vertices;
  nan(3, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(kind_of([&] { render_png(nan, cube.faces); }, nullptr, &field), ErrorKind::InvalidArgument);
  EXPECT_EQ(field, "vertices");
  Vertices inf = cube.vertices;
  inf(0, 0) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(render_png(inf, cube.faces), Error);

  Faces bad = cube.faces;
  bad(5, 2) = 8;
  EXPECT_EQ(kind_of([&] { render_png(cube.vertices, bad); }, nullptr, &field), ErrorKind::InvalidArgument);
  EXPECT_EQ(field, "faces");
  bad(5, 2) = -1;
  EXPECT_THROW(render_png(cube.vertices, bad), Error);

  RenderOptions o;
  o.width = 0;
  EXPECT_EQ(kind_of([&] { render_png(cube.vertices, cube.faces, o); }, nullptr, &field), ErrorKind::InvalidArgument);
  EXPECT_EQ(field, "width");
  o = {};
  o.height = 100000;
  EXPECT_EQ(kind_of([&] { render_png(cube.vertices, cube.faces, o); }, nullptr, &field), ErrorKind::InvalidArgument);
  EXPECT_EQ(field, "height");
  o = {};
  o.body_rgb = {std::numeric_limits<float>::quiet_NaN(), 0.5f, 0.5f};
  EXPECT_THROW(render_png(cube.vertices, cube.faces, o), Error);
  o = {};
  o.vertex_scalar = {1, 2, 3};
  EXPECT_EQ(kind_of([&] { render_png(cube.vertices, cube.faces, o); }, nullptr, &field), ErrorKind::InvalidArgument);
  EXPECT_EQ(field, "vertex_scalar");
  o.vertex_scalar.assign(8, 1.0f);
  o.vertex_scalar[2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(render_png(cube.vertices, cube.faces, o), Error);

  EXPECT_EQ(kind_of([&] { render_views_png(cube.vertices, cube.faces, {}); }, nullptr, &field), ErrorKind::InvalidArgument);
  EXPECT_EQ(field, "views");

  o = {};
  o.focus_radius = -1;
  EXPECT_EQ(kind_of([&] { render_png(cube.vertices, cube.faces, o); }, nullptr, &field), ErrorKind::InvalidArgument);
  EXPECT_EQ(field, "focus_radius");
  o.focus_radius = 0.1;
  o.focus_center[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(kind_of([&] { render_png(cube.vertices, cube.faces, o); }, nullptr, &field), ErrorKind::InvalidArgument);
  EXPECT_EQ(field, "focus_center");
}

TEST(UvAtlas, DrawsEachTriangleWhereItsUvsAreAndFlippedOnesRed) {
  UvCoordinates uv(6, 2);
  uv << 0.05, 0.05, 0.45, 0.05, 0.05, 0.45,  // counter-clockwise, lower left
      0.55, 0.55, 0.55, 0.95, 0.95, 0.55;    // clockwise (flipped), upper right
  Faces f(2, 3);
  f << 0, 1, 2, 3, 4, 5;
  UvAtlasOptions o;
  o.size = 100;
  const Image img = decode(render_uv_atlas_png(uv, f, o));
  ASSERT_EQ(img.width, 100);
  ASSERT_EQ(img.height, 100);
  auto rgb = [&](int x, int y) { return std::array<int, 3>{img.at(x, y)[0], img.at(x, y)[1], img.at(x, y)[2]}; };
  // Pixel (x, y) = (u·size, (1 − v)·size): v = 1 is the image's top row.
  EXPECT_EQ(rgb(15, 85), (std::array<int, 3>{222, 222, 222}));  // inside the lower-left one
  EXPECT_EQ(rgb(65, 35), (std::array<int, 3>{240, 120, 120}));  // inside the flipped one
  EXPECT_EQ(rgb(90, 90), (std::array<int, 3>{255, 255, 255}));  // outside both
  EXPECT_EQ(rgb(15, 35), (std::array<int, 3>{255, 255, 255}));
  EXPECT_EQ(rgb(25, 95), (std::array<int, 3>{60, 60, 70}));     // on the edge v = 0.05
  // Bad input.
  std::string field;
  o.size = 8;
  EXPECT_EQ(kind_of([&] { render_uv_atlas_png(uv, f, o); }, nullptr, &field), ErrorKind::InvalidArgument);
  EXPECT_EQ(field, "size");
  o.size = 64;
  Faces bad = f;
  bad(1, 2) = 6;
  EXPECT_EQ(kind_of([&] { render_uv_atlas_png(uv, bad, o); }, nullptr, &field), ErrorKind::InvalidArgument);
  EXPECT_EQ(field, "uv_faces");
}

}  // namespace
}  // namespace caliper
