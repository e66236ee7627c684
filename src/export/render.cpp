// CPU rasterizer for preview pictures: a deferred z-buffer rasterizer over a 3×3 supersampled
// grid, perspective-correct interpolation of per-vertex normals, Blinn-Phong shading (key light,
// fill light, sky/ground hemisphere ambient, a faint rim), and a floor with a fading grid and a
// soft shadow made from a blurred height map of the body seen from a high light. Colour is computed in
// linear light and stored as sRGB.
#include "caliper/export/render.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "caliper/errors.h"

namespace caliper {

const char* to_string(View view) {
  switch (view) {
    case View::Front: return "front";
    case View::Side: return "side";
    case View::Back: return "back";
    case View::ThreeQuarter: return "three_quarter";
    case View::Top: return "top";
  }
  return "unknown";
}

namespace {

using Vec3 = Eigen::Vector3d;
using Rgb = Eigen::Vector3f;

constexpr int kSupersample = 3;                                   // 3×3 samples per pixel
constexpr double kFovY = 30.0 * std::numbers::pi / 180.0;         // vertical field of view
constexpr double kPitch = 6.0 * std::numbers::pi / 180.0;         // camera looks slightly down
constexpr double kTopLean = 15.0 * std::numbers::pi / 180.0;       // the top view, from the vertical
constexpr double kFill = 0.86;                                    // fraction of the half-frame the mesh may use
constexpr double kNear = 0.02;                                    // metres in front of the eye
constexpr int kMaxSide = 4096;
constexpr size_t kMaxViews = 8;

float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}
float linear_to_srgb(float c) {
  c = std::clamp(c, 0.0f, 1.0f);
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}
Rgb srgb(float r, float g, float b) { return {srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b)}; }

double smoothstep(double a, double b, double x) {
  const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

// Blue → cyan → green → yellow → red, t in [0, 1]; returned in linear light.
Rgb heat_colour(float t) {
  static const float stops[5][3] = {{0.13f, 0.27f, 0.85f}, {0.12f, 0.72f, 0.90f}, {0.35f, 0.80f, 0.30f},
                                    {0.96f, 0.80f, 0.15f}, {0.86f, 0.16f, 0.11f}};
  const float x = std::clamp(t, 0.0f, 1.0f) * 4.0f;
  const int i = std::min(static_cast<int>(x), 3);
  const float u = x - static_cast<float>(i);
  Rgb c;
  for (int k = 0; k < 3; ++k) c[k] = srgb_to_linear(stops[i][k] * (1 - u) + stops[i + 1][k] * u);
  return c;
}

// Soft floor shadow: for each cell of a square grid on the floor, the nearest body point along
// the shadow light, turned into a tight "contact" darkness and a wide "ambient" darkness, each blurred.
struct ShadowMap {
  double x0 = 0, z0 = 0, cell = 1;
  int n = 0;
  std::vector<float> darkness;  // multiplicative floor factor, 1 = unshadowed

  float at(double x, double z) const {
    if (n == 0) return 1.0f;
    const double gx = (x - x0) / cell - 0.5, gz = (z - z0) / cell - 0.5;
    if (gx < 0 || gz < 0 || gx >= n - 1 || gz >= n - 1) return 1.0f;
    const int ix = static_cast<int>(gx), iz = static_cast<int>(gz);
    const float fx = static_cast<float>(gx - ix), fz = static_cast<float>(gz - iz);
    auto d = [&](int i, int j) { return darkness[static_cast<size_t>(j) * n + i]; };
    return (d(ix, iz) * (1 - fx) + d(ix + 1, iz) * fx) * (1 - fz) +
           (d(ix, iz + 1) * (1 - fx) + d(ix + 1, iz + 1) * fx) * fz;
  }
};

// Three passes of a box blur approximate a Gaussian; radius in cells.
void blur(std::vector<float>& img, int n, int radius) {
  if (radius <= 0) return;
  std::vector<float> tmp(img.size());
  for (int pass = 0; pass < 3; ++pass) {
    for (int axis = 0; axis < 2; ++axis) {
      for (int line = 0; line < n; ++line) {
        auto idx = [&](int i) { return axis == 0 ? static_cast<size_t>(line) * n + i : static_cast<size_t>(i) * n + line; };
        double sum = 0;
        for (int i = -radius; i <= radius; ++i) sum += img[idx(std::clamp(i, 0, n - 1))];
        for (int i = 0; i < n; ++i) {
          tmp[idx(i)] = static_cast<float>(sum / (2 * radius + 1));
          sum += img[idx(std::min(i + radius + 1, n - 1))] - img[idx(std::max(i - radius, 0))];
        }
      }
      img.swap(tmp);
    }
  }
}

// Everything about the mesh that does not depend on the view.
struct Scene {
  const Vertices* vertices = nullptr;
  const Faces* faces = nullptr;
  Vertices normals;
  std::vector<float> scalar_t;  // per-vertex heat-map coordinate in [0, 1], or empty
  const UvCoordinates* uv = nullptr;  // checker texture coordinates, or null
  const Faces* uv_faces = nullptr;
  int checker_squares = 0;
  Rgb albedo;                   // linear
  Vec3 lo, hi, target;
  double floor_y = 0;
  bool floor = true;
};

// `toward_light` (unit, pointing up) is the direction the shadow is cast from: each body point
// lands on the floor along it, and its distance along it is the height that sets the darkness.
ShadowMap build_shadow(const Scene& s, const Vec3& toward_light) {
  ShadowMap m;
  const Vertices& v = *s.vertices;
  const Eigen::Index nv = v.rows();
  std::vector<double> fx(nv), fz(nv), dist(nv);
  double reach = 0;
  for (Eigen::Index i = 0; i < nv; ++i) {
    const double h = std::max(0.0, v(i, 1) - s.floor_y);
    dist[i] = h / toward_light.y();
    fx[i] = v(i, 0) - toward_light.x() * dist[i];
    fz[i] = v(i, 2) - toward_light.z() * dist[i];
    reach = std::max(reach, std::hypot(fx[i] - s.target.x(), fz[i] - s.target.z()));
  }
  const double half = reach + 0.5;  // room for the blur beyond the silhouette
  m.n = 256;
  m.cell = 2 * half / m.n;
  m.x0 = s.target.x() - half;
  m.z0 = s.target.z() - half;
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> height(static_cast<size_t>(m.n) * m.n, inf);
  const Faces& f = *s.faces;
  for (Eigen::Index t = 0; t < f.rows(); ++t) {
    double px[3], pz[3], py[3];
    for (int k = 0; k < 3; ++k) {
      px[k] = (fx[f(t, k)] - m.x0) / m.cell;
      pz[k] = (fz[f(t, k)] - m.z0) / m.cell;
      py[k] = dist[f(t, k)];
    }
    const double area = (px[1] - px[0]) * (pz[2] - pz[0]) - (px[2] - px[0]) * (pz[1] - pz[0]);
    if (std::abs(area) < 1e-12) continue;  // seen edge-on from the light: neighbours cover it
    const int xa = std::max(0, static_cast<int>(std::floor(std::min({px[0], px[1], px[2]}))));
    const int xb = std::min(m.n - 1, static_cast<int>(std::ceil(std::max({px[0], px[1], px[2]}))));
    const int za = std::max(0, static_cast<int>(std::floor(std::min({pz[0], pz[1], pz[2]}))));
    const int zb = std::min(m.n - 1, static_cast<int>(std::ceil(std::max({pz[0], pz[1], pz[2]}))));
    for (int gz = za; gz <= zb; ++gz)
      for (int gx = xa; gx <= xb; ++gx) {
        const double cx = gx + 0.5, cz = gz + 0.5;
        const double w0 = ((px[1] - cx) * (pz[2] - cz) - (px[2] - cx) * (pz[1] - cz)) / area;
        const double w1 = ((px[2] - cx) * (pz[0] - cz) - (px[0] - cx) * (pz[2] - cz)) / area;
        const double w2 = 1 - w0 - w1;
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        float& h = height[static_cast<size_t>(gz) * m.n + gx];
        h = std::min(h, static_cast<float>(w0 * py[0] + w1 * py[1] + w2 * py[2]));
      }
  }
  std::vector<float> contact(height.size()), ambient(height.size());
  for (size_t i = 0; i < height.size(); ++i) {
    contact[i] = std::isinf(height[i]) ? 0.0f : std::exp(-height[i] / 0.05f);
    ambient[i] = std::isinf(height[i]) ? 0.0f : std::exp(-height[i] / 1.2f);
  }
  blur(contact, m.n, std::max(1, static_cast<int>(0.03 / m.cell)));
  blur(ambient, m.n, std::max(1, static_cast<int>(0.10 / m.cell)));
  m.darkness.resize(height.size());
  for (size_t i = 0; i < height.size(); ++i)
    m.darkness[i] = (1 - 0.55f * std::min(contact[i], 1.0f)) * (1 - 0.40f * std::min(ambient[i], 1.0f));
  return m;
}

Scene make_scene(const Vertices& vertices, const Faces& faces, const RenderOptions& o) {
  if (vertices.rows() == 0) throw Error(ErrorKind::InvalidArgument, "cannot render an empty mesh: no vertices", "vertices");
  if (faces.rows() == 0) throw Error(ErrorKind::InvalidArgument, "cannot render an empty mesh: no faces", "faces");
  if (!vertices.allFinite()) throw Error(ErrorKind::InvalidArgument, "vertices contain NaN or infinite values", "vertices");
  if (!(std::isfinite(o.focus_radius) && o.focus_radius >= 0))
    throw Error(ErrorKind::InvalidArgument, "focus_radius must be a finite length >= 0 (metres)", "focus_radius");
  for (double c : o.focus_center)
    if (!std::isfinite(c)) throw Error(ErrorKind::InvalidArgument, "focus_center must be finite", "focus_center");
  if (faces.minCoeff() < 0 || faces.maxCoeff() >= vertices.rows())
    throw Error(ErrorKind::InvalidArgument, "face index out of range [0, " + std::to_string(vertices.rows()) + ")", "faces");
  if (o.width < 1 || o.height < 1 || o.width > kMaxSide || o.height > kMaxSide)
    throw Error(ErrorKind::InvalidArgument, "image width and height must be 1.." + std::to_string(kMaxSide) + " pixels",
                o.width < 1 || o.width > kMaxSide ? "width" : "height");
  for (float c : o.body_rgb)
    if (!(c >= 0.0f && c <= 1.0f)) throw Error(ErrorKind::InvalidArgument, "body colour components must be in [0, 1]", "body_rgb");
  if (o.uv_faces.rows() > 0) {
    if (o.uv_faces.rows() != faces.rows())
      throw Error(ErrorKind::InvalidArgument, "uv_faces needs one row per face", "uv_faces");
    if (o.uv_faces.minCoeff() < 0 || o.uv_faces.maxCoeff() >= o.uv_coordinates.rows())
      throw Error(ErrorKind::InvalidArgument, "UV index out of range", "uv_faces");
    if (!o.uv_coordinates.allFinite())
      throw Error(ErrorKind::InvalidArgument, "UV coordinates contain NaN or infinite values", "uv_coordinates");
    if (o.checker_squares < 1 || o.checker_squares > 4096)
      throw Error(ErrorKind::InvalidArgument, "checker_squares must be in [1, 4096]", "checker_squares");
  }

  Scene s;
  if (o.uv_faces.rows() > 0) {
    s.uv = &o.uv_coordinates;
    s.uv_faces = &o.uv_faces;
    s.checker_squares = o.checker_squares;
  }
  s.vertices = &vertices;
  s.faces = &faces;
  s.normals = vertex_normals(vertices, faces);
  s.albedo = srgb(o.body_rgb[0], o.body_rgb[1], o.body_rgb[2]);
  s.floor = o.floor_grid;
  if (!o.vertex_scalar.empty()) {
    if (static_cast<Eigen::Index>(o.vertex_scalar.size()) != vertices.rows())
      throw Error(ErrorKind::InvalidArgument,
                  "vertex_scalar has " + std::to_string(o.vertex_scalar.size()) + " values for " +
                      std::to_string(vertices.rows()) + " vertices",
                  "vertex_scalar");
    if (!std::isfinite(o.scalar_min) || !std::isfinite(o.scalar_max))
      throw Error(ErrorKind::InvalidArgument, "scalar range must be finite", "scalar_min");
    float lo = o.scalar_min, hi = o.scalar_max;
    if (lo == hi) {
      lo = std::numeric_limits<float>::infinity();
      hi = -lo;
      for (float x : o.vertex_scalar) {
        if (!std::isfinite(x)) throw Error(ErrorKind::InvalidArgument, "vertex_scalar contains NaN or infinite values", "vertex_scalar");
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
    }
    s.scalar_t.resize(o.vertex_scalar.size());
    for (size_t i = 0; i < s.scalar_t.size(); ++i) {
      const float x = o.vertex_scalar[i];
      if (!std::isfinite(x)) throw Error(ErrorKind::InvalidArgument, "vertex_scalar contains NaN or infinite values", "vertex_scalar");
      s.scalar_t[i] = hi > lo ? std::clamp((x - lo) / (hi - lo), 0.0f, 1.0f) : 0.5f;
    }
  }
  s.lo = vertices.colwise().minCoeff().transpose();
  s.hi = vertices.colwise().maxCoeff().transpose();
  s.target = 0.5 * (s.lo + s.hi);
  s.floor_y = s.lo.y();
  return s;
}

// A camera looking at the scene's target from a view direction. Normalised device coordinates
// (NDC) run −1..1 across the image; `shift` recentres the mesh after fitting.
struct Camera {
  Vec3 eye, right, up, forward;
  bool ortho = false;
  double tan_x = 1, tan_y = 1;      // perspective: tangent of the half field of view
  double half_x = 1, half_y = 1;    // orthographic: half the frame in metres
  double shift_x = 0, shift_y = 0;  // NDC offset
  ShadowMap shadow;                 // soft floor shadow for this view's lighting

  // NDC x, y and the depth in front of the eye.
  Vec3 project(const Vec3& p) const {
    const Vec3 r = p - eye;
    const double depth = r.dot(forward);
    if (ortho) return {r.dot(right) / half_x + shift_x, r.dot(up) / half_y + shift_y, depth};
    return {r.dot(right) / (depth * tan_x) + shift_x, r.dot(up) / (depth * tan_y) + shift_y, depth};
  }
  // Ray through NDC (nx, ny): origin and unit direction.
  void ray(double nx, double ny, Vec3& origin, Vec3& dir) const {
    nx -= shift_x;
    ny -= shift_y;
    if (ortho) {
      origin = eye + right * (nx * half_x) + up * (ny * half_y);
      dir = forward;
    } else {
      origin = eye;
      dir = (forward + right * (nx * tan_x) + up * (ny * tan_y)).normalized();
    }
  }
};

// From the target toward the camera: the side views look slightly down (kPitch); the top view
// leans toward the front so that the image's up (away from the body's front) is well defined.
Vec3 toward_camera(View view) {
  const double s = std::sqrt(0.5);
  Vec3 horizontal{0, 0, 1};
  switch (view) {
    case View::Front: break;
    case View::Side: horizontal = {1, 0, 0}; break;
    case View::Back: horizontal = {0, 0, -1}; break;
    case View::ThreeQuarter: horizontal = {s, 0, s}; break;
    case View::Top: return Vec3(0, std::cos(kTopLean), std::sin(kTopLean));
  }
  return horizontal * std::cos(kPitch) + Vec3::UnitY() * std::sin(kPitch);
}

// Orientation only; distance and frame size come from fit_scale.
Camera orient(const Scene& s, View view, const RenderOptions& o) {
  Camera c;
  c.forward = -toward_camera(view);
  c.right = c.forward.cross(Vec3::UnitY()).normalized();
  c.up = c.right.cross(c.forward);
  c.ortho = o.orthographic;
  const double aspect = static_cast<double>(o.width) / o.height;
  c.tan_y = std::tan(kFovY / 2);
  c.tan_x = c.tan_y * aspect;
  c.eye = s.target;
  return c;
}

// The scale that fits the mesh for this view: perspective → the eye distance, orthographic →
// the half frame height. Taking the largest over several views gives them one common scale.
double fit_scale(const Scene& s, const Camera& c, double aspect) {
  const Vertices& v = *s.vertices;
  double need = c.ortho ? 1e-6 : kNear;
  for (Eigen::Index i = 0; i < v.rows(); ++i) {
    const Vec3 r = v.row(i).transpose() - s.target;
    const double x = std::abs(r.dot(c.right)), y = std::abs(r.dot(c.up)), z = -r.dot(c.forward);
    if (c.ortho) {
      need = std::max({need, y / kFill, x / (aspect * kFill)});
    } else {
      // A point at lateral offset x and depth d − z stays inside when x ≤ tan·fill·(d − z).
      need = std::max({need, z + x / (c.tan_x * kFill), z + y / (c.tan_y * kFill), z + kNear});
    }
  }
  return need;
}

void apply_scale(const Scene& s, Camera& c, double scale, double aspect) {
  if (c.ortho) {
    c.half_y = scale;
    c.half_x = scale * aspect;
    const Vertices& v = *s.vertices;
    double far = 0;
    for (Eigen::Index i = 0; i < v.rows(); ++i) far = std::max(far, (v.row(i).transpose() - s.target).norm());
    c.eye = s.target - c.forward * (far + 1.0);
  } else {
    c.eye = s.target - c.forward * scale;
  }
}

// A close-up: the camera looks at the focus point from far enough that a sphere of the focus
// radius fills kFill of the frame's smaller half-extent; no recentring.
void frame_close_up(const Scene& s, Camera& c, const RenderOptions& o, double aspect) {
  const Vec3 centre(o.focus_center[0], o.focus_center[1], o.focus_center[2]);
  const double r = o.focus_radius / kFill;
  if (c.ortho) {
    c.half_y = r / std::min(1.0, aspect);
    c.half_x = c.half_y * aspect;
    const Vertices& v = *s.vertices;
    double far = 0;
    for (Eigen::Index i = 0; i < v.rows(); ++i) far = std::max(far, (v.row(i).transpose() - centre).norm());
    c.eye = centre - c.forward * (far + 1.0);
  } else {
    const double t = std::min(c.tan_x, c.tan_y);  // the sphere's tangent cone fits the frame
    c.eye = centre - c.forward * (r * std::sqrt(1 + t * t) / t);
  }
}

// NDC bounding box of the projected mesh (x min, x max, y min, y max).
std::array<double, 4> ndc_bounds(const Scene& s, const Camera& c) {
  std::array<double, 4> b{1e300, -1e300, 1e300, -1e300};
  const Vertices& v = *s.vertices;
  for (Eigen::Index i = 0; i < v.rows(); ++i) {
    const Vec3 p = c.project(v.row(i).transpose());
    b[0] = std::min(b[0], p.x());
    b[1] = std::max(b[1], p.x());
    b[2] = std::min(b[2], p.y());
    b[3] = std::max(b[3], p.y());
  }
  return b;
}

struct Lights {
  Vec3 key, fill;
  Rgb key_rgb, fill_rgb, sky, ground;
};

// Studio lighting fixed to the camera, so every view is lit alike: a warm key from the upper
// left, a cool fill from the right, a sky/ground hemisphere for ambient.
Lights camera_lights(const Camera& c) {
  Lights l;
  l.key = (-0.75 * c.right + 0.70 * c.up - 0.70 * c.forward).normalized();
  l.fill = (0.85 * c.right + 0.10 * c.up - 0.55 * c.forward).normalized();
  l.key_rgb = Rgb(1.00f, 0.97f, 0.92f) * 0.95f;
  l.fill_rgb = Rgb(0.86f, 0.91f, 1.00f) * 0.30f;
  l.sky = Rgb(0.92f, 0.94f, 1.00f) * 0.24f;
  l.ground = Rgb(0.60f, 0.56f, 0.52f) * 0.22f;
  return l;
}

Rgb shade_body(const Scene& s, const Camera& c, const Lights& l, const Vec3& p, Vec3 n, float scalar_t,
               const Rgb* texture = nullptr) {
  const Vec3 to_eye = c.ortho ? Vec3(-c.forward) : Vec3((c.eye - p).normalized());
  if (n.dot(to_eye) < 0) n = -n;  // inside of an open or inconsistently wound mesh
  const Rgb albedo = texture ? *texture : s.scalar_t.empty() ? s.albedo : heat_colour(scalar_t);
  const float hemi = static_cast<float>(0.5 + 0.5 * n.y());
  Rgb diffuse = l.ground * (1 - hemi) + l.sky * hemi;
  Rgb specular = Rgb::Zero();
  const Vec3* dirs[2] = {&l.key, &l.fill};
  const Rgb* cols[2] = {&l.key_rgb, &l.fill_rgb};
  for (int i = 0; i < 2; ++i) {
    const double nl = n.dot(*dirs[i]);
    // Slightly wrapped Lambert: softer terminator, like a matte painted mannequin.
    const double wrap = std::max(0.0, (nl + 0.15) / 1.15);
    diffuse += *cols[i] * static_cast<float>(wrap);
    if (nl > 0) {
      const double nh = std::max(0.0, n.dot((*dirs[i] + to_eye).normalized()));
      specular += *cols[i] * static_cast<float>(0.16 * std::pow(nh, 40.0));
    }
  }
  const double rim = std::pow(1.0 - std::clamp(n.dot(to_eye), 0.0, 1.0), 4.0);
  return albedo.cwiseProduct(diffuse) + specular + l.sky * static_cast<float>(0.35 * rim);
}

// Background: a vertical light-grey gradient (linear light), lighter at the top.
Rgb background(double v) {  // v = 0 at the top of the image, 1 at the bottom
  const float t = static_cast<float>(v);
  return srgb(0.93f, 0.93f, 0.94f) * (1 - t) + srgb(0.80f, 0.80f, 0.81f) * t;
}

Rgb shade_floor(const Scene& s, const Camera& c, double nx, double ny, double v, double sample_angle) {
  const Rgb bg = background(v);
  if (!s.floor) return bg;
  Vec3 origin, dir;
  c.ray(nx, ny, origin, dir);
  if (dir.y() >= -1e-9) return bg;
  const double t = (s.floor_y - origin.y()) / dir.y();
  if (t <= 0) return bg;
  const Vec3 p = origin + dir * t;
  const double r = std::hypot(p.x() - s.target.x(), p.z() - s.target.z());
  const double radius = std::max(s.hi.x() - s.lo.x(), s.hi.z() - s.lo.z()) * 0.5;
  const double fade = 1 - smoothstep(radius + 0.5, radius + 2.0, r);
  float f = c.shadow.at(p.x(), p.z());
  if (fade > 0) {
    // Grid every 25 cm. The sample's footprint on the floor widens at grazing angles; lines
    // thinner than it are drawn fainter instead of flickering.
    const double spacing = 0.25, half_width = 0.0035;
    const double footprint = (c.ortho ? sample_angle : t * sample_angle) / std::max(std::abs(dir.y()), 0.05);
    const double w = std::max(half_width, 0.5 * footprint);
    auto line = [&](double x) {
      const double d = std::abs(x / spacing - std::round(x / spacing)) * spacing;
      return (1 - smoothstep(w * 0.5, w * 1.5, d)) * (half_width / w);
    };
    const double g = std::max(line(p.x()), line(p.z()));
    f *= static_cast<float>(1 - 0.22 * g * fade);
  }
  return bg * f;
}

// Renders one view into `out` (linear RGB, width×height), at a given camera.
void render_view(const Scene& s, const Camera& c, int width, int height, std::vector<Rgb>& out) {
  const int sw = width * kSupersample, sh = height * kSupersample;
  const size_t count = static_cast<size_t>(sw) * sh;
  std::vector<float> closeness(count, -std::numeric_limits<float>::infinity());
  std::vector<std::int32_t> tri(count, -1);
  std::vector<float> bary(count * 2);

  const Vertices& v = *s.vertices;
  const Faces& f = *s.faces;
  // Screen positions in sample units, and a depth key that is affine in screen space
  // (1/depth for perspective, −depth for orthographic): larger is closer.
  std::vector<double> sx(v.rows()), sy(v.rows()), key(v.rows()), depth(v.rows());
  for (Eigen::Index i = 0; i < v.rows(); ++i) {
    const Vec3 p = c.project(v.row(i).transpose());
    sx[i] = (p.x() + 1) * 0.5 * sw;
    sy[i] = (1 - p.y()) * 0.5 * sh;
    depth[i] = p.z();
    key[i] = c.ortho ? -p.z() : 1.0 / p.z();
  }
  for (Eigen::Index t = 0; t < f.rows(); ++t) {
    const int a = f(t, 0), b = f(t, 1), d = f(t, 2);
    if (!c.ortho && (depth[a] < kNear || depth[b] < kNear || depth[d] < kNear)) continue;
    const double area = (sx[b] - sx[a]) * (sy[d] - sy[a]) - (sx[d] - sx[a]) * (sy[b] - sy[a]);
    if (std::abs(area) < 1e-12) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({sx[a], sx[b], sx[d]}) - 0.5)));
    const int x1 = std::min(sw - 1, static_cast<int>(std::ceil(std::max({sx[a], sx[b], sx[d]}) - 0.5)));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({sy[a], sy[b], sy[d]}) - 0.5)));
    const int y1 = std::min(sh - 1, static_cast<int>(std::ceil(std::max({sy[a], sy[b], sy[d]}) - 0.5)));
    for (int y = y0; y <= y1; ++y) {
      const double py = y + 0.5;
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5;
        // Barycentric weights from edge functions; dividing by the signed area makes them
        // positive inside whichever way the triangle winds on screen.
        const double w0 = ((sx[b] - px) * (sy[d] - py) - (sx[d] - px) * (sy[b] - py)) / area;
        const double w1 = ((sx[d] - px) * (sy[a] - py) - (sx[a] - px) * (sy[d] - py)) / area;
        const double w2 = 1 - w0 - w1;
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        const double k = w0 * key[a] + w1 * key[b] + w2 * key[d];
        const size_t i = static_cast<size_t>(y) * sw + x;
        if (k <= closeness[i]) continue;
        closeness[i] = static_cast<float>(k);
        tri[i] = static_cast<std::int32_t>(t);
        // Perspective-correct weights: attributes are affine in 1/depth-weighted space.
        double p0 = w0, p1 = w1, p2 = w2;
        if (!c.ortho) {
          p0 *= key[a];
          p1 *= key[b];
          p2 *= key[d];
          const double sum = p0 + p1 + p2;
          p0 /= sum;
          p1 /= sum;
        }
        bary[2 * i] = static_cast<float>(p0);
        bary[2 * i + 1] = static_cast<float>(p1);
      }
    }
  }

  const Lights lights = camera_lights(c);
  // Angle (perspective) or length (orthographic) one sample spans, for grid filtering.
  const double sample_angle = c.ortho ? 2 * c.half_y / sh : 2 * c.tan_y / sh;
  out.assign(static_cast<size_t>(width) * height, Rgb::Zero());
  const float norm = 1.0f / (kSupersample * kSupersample);
  for (int y = 0; y < sh; ++y) {
    const double ny = 1 - 2 * (y + 0.5) / sh;
    const double vv = (y + 0.5) / sh;
    for (int x = 0; x < sw; ++x) {
      const size_t i = static_cast<size_t>(y) * sw + x;
      const double nx = 2 * (x + 0.5) / sw - 1;
      Rgb colour;
      if (tri[i] < 0) {
        colour = shade_floor(s, c, nx, ny, vv, sample_angle);
      } else {
        const int t = tri[i];
        const double b0 = bary[2 * i], b1 = bary[2 * i + 1], b2 = 1 - b0 - b1;
        const int ia = f(t, 0), ib = f(t, 1), ic = f(t, 2);
        const Vec3 p = b0 * v.row(ia).transpose() + b1 * v.row(ib).transpose() + b2 * v.row(ic).transpose();
        Vec3 n = b0 * s.normals.row(ia).transpose() + b1 * s.normals.row(ib).transpose() +
                 b2 * s.normals.row(ic).transpose();
        const double len = n.norm();
        n = len > 1e-12 ? Vec3(n / len) : Vec3(-c.forward);
        float st = 0;
        if (!s.scalar_t.empty())
          st = static_cast<float>(b0 * s.scalar_t[ia] + b1 * s.scalar_t[ib] + b2 * s.scalar_t[ic]);
        if (s.uv) {  // checker texture: light and dark squares of the unit UV square
          const auto& uf = *s.uv_faces;
          const Eigen::Vector2d q = b0 * s.uv->row(uf(t, 0)).transpose() + b1 * s.uv->row(uf(t, 1)).transpose() +
                                    b2 * s.uv->row(uf(t, 2)).transpose();
          const auto cell = static_cast<long>(std::floor(q.x() * s.checker_squares)) +
                            static_cast<long>(std::floor(q.y() * s.checker_squares));
          const Rgb texture = (cell & 1) ? Rgb(0.10f, 0.14f, 0.22f) : Rgb(0.78f, 0.72f, 0.62f);
          colour = shade_body(s, c, lights, p, n, st, &texture);
        } else {
          colour = shade_body(s, c, lights, p, n, st);
        }
      }
      out[static_cast<size_t>(y / kSupersample) * width + x / kSupersample] += colour * norm;
    }
  }
}

void validate_views(const std::vector<View>& views) {
  if (views.empty() || views.size() > kMaxViews)
    throw Error(ErrorKind::InvalidArgument, "need 1.." + std::to_string(kMaxViews) + " views", "views");
  for (View view : views)
    if (view != View::Front && view != View::Side && view != View::Back && view != View::ThreeQuarter && view != View::Top)
      throw Error(ErrorKind::InvalidArgument, "unknown view", "views");
}

std::string render_impl(const Vertices& vertices, const Faces& faces, const std::vector<View>& views,
                        const RenderOptions& o) {
  validate_views(views);
  const Scene s = make_scene(vertices, faces, o);
  const double aspect = static_cast<double>(o.width) / o.height;
  std::vector<Camera> cams;
  double scale = 0;
  for (View view : views) {
    cams.push_back(orient(s, view, o));
    scale = std::max(scale, fit_scale(s, cams.back(), aspect));
  }
  if (o.focus_radius > 0) {
    for (Camera& c : cams) frame_close_up(s, c, o, aspect);
  } else {
    // One scale for all; centre each view horizontally on its own, but share the vertical shift
    // so the floor lines up across panels.
    double ylo = 1e300, yhi = -1e300;
    for (Camera& c : cams) {
      apply_scale(s, c, scale, aspect);
      const auto b = ndc_bounds(s, c);
      c.shift_x = -(b[0] + b[1]) / 2;
      ylo = std::min(ylo, b[2]);
      yhi = std::max(yhi, b[3]);
    }
    for (Camera& c : cams) c.shift_y = -(ylo + yhi) / 2;
  }
  // The floor shadow falls from a high light on the key light's side, so it shows beside and
  // behind the body rather than hiding under it.
  for (Camera& c : cams)
    if (s.floor) c.shadow = build_shadow(s, (-0.35 * c.right + 1.0 * Vec3::UnitY() - 0.25 * c.forward).normalized());

  const int total_width = o.width * static_cast<int>(views.size());
  std::vector<std::uint8_t> rgb(static_cast<size_t>(total_width) * o.height * 3);
  std::vector<Rgb> panel;
  for (size_t k = 0; k < cams.size(); ++k) {
    render_view(s, cams[k], o.width, o.height, panel);
    for (int y = 0; y < o.height; ++y)
      for (int x = 0; x < o.width; ++x) {
        const Rgb& c = panel[static_cast<size_t>(y) * o.width + x];
        const size_t at = (static_cast<size_t>(y) * total_width + k * o.width + x) * 3;
        for (int ch = 0; ch < 3; ++ch)
          rgb[at + ch] = static_cast<std::uint8_t>(std::lround(linear_to_srgb(c[ch]) * 255.0f));
      }
  }
  return encode_png_rgb8(total_width, o.height, rgb);
}

}  // namespace

std::string render_png(const Vertices& vertices, const Faces& faces, const RenderOptions& options) {
  return render_impl(vertices, faces, {options.view}, options);
}

std::string render_views_png(const Vertices& vertices, const Faces& faces, const std::vector<View>& views,
                             const RenderOptions& options) {
  return render_impl(vertices, faces, views, options);
}

}  // namespace caliper
