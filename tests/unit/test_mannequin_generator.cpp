// The built-in body generator: topology invariants, landmark sanity, fidelity to ANSUR inputs
// (measured by Caliper's own measurement code), rig sanity and input validation.
#include <gtest/gtest.h>

#include <random>

#include "caliper/body/crease.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <numbers>
#include <optional>

#include "caliper/body/crease.h"
#include "caliper/body/mesh.h"
#include "caliper/body/pose.h"
#include "caliper/errors.h"
#include "caliper/mannequin/population.h"
#include "caliper/io/ansur.h"
#include "caliper/mannequin/generator.h"
#include "caliper/measure/geometry.h"
#include "caliper/measure/measure.h"
#include "fixtures.h"

using namespace caliper;
namespace mq = caliper::mannequin;

namespace {

BodyModel model_for(const Vertices& v, Sex sex) { return mq::measuring_model(v, sex); }

std::vector<std::pair<mq::Dimensions, Sex>> sample_bodies() {
  std::vector<std::pair<mq::Dimensions, Sex>> out;
  for (Sex s : {Sex::Female, Sex::Male, Sex::Neutral}) out.push_back({mq::typical_dimensions(s), s});
  // Tall-thin and short-heavy variants built from the typical values.
  auto tall = mq::complete_dimensions({{"stature", 1.95}}, Sex::Male);
  for (auto c : {"chestcircumference", "waistcircumference", "buttockcircumference", "thighcircumference"}) tall[c] *= 0.85;
  out.push_back({tall, Sex::Male});
  auto short_heavy = mq::complete_dimensions({{"stature", 1.50}}, Sex::Female);
  for (auto c : {"chestcircumference", "waistcircumference", "buttockcircumference", "thighcircumference",
                 "waistdepth", "waistbreadth", "buttockdepth", "hipbreadth"})
    short_heavy[c] *= 1.3;
  out.push_back({short_heavy, Sex::Female});
  return out;
}


// Where the plane y = h meets face i's edges: `add` gets each corner on the plane and each point
// where an edge crosses it. The checks below cut the whole mesh dozens of times per body; reading
// the coordinates through pointers (Vertices and Faces are row-major) keeps that cheap in the
// sanitizer build, where every small Eigen copy is a call (the population test took 147 s there).
template <class Add>
void face_cuts(const Vertices& v, const Faces& f, Eigen::Index i, double h, Add&& add) {
  static_assert(Vertices::IsRowMajor != 0 && Faces::IsRowMajor != 0);
  const std::int32_t* corner = f.data() + 3 * i;
  for (int c = 0; c < 3; ++c) {
    const double *a = v.data() + 3 * corner[c], *b = v.data() + 3 * corner[(c + 1) % 3];
    if (a[1] == h) add(Eigen::Vector3d(a[0], a[1], a[2]));
    if ((a[1] - h) * (b[1] - h) >= 0) continue;
    const double t = (h - a[1]) / (b[1] - a[1]);
    add(Eigen::Vector3d(a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t));
  }
}
// Where the plane y = h cuts the mesh's edges.
std::vector<Eigen::Vector3d> cut(const Vertices& v, const Faces& f, double h) {
  std::vector<Eigen::Vector3d> out;
  for (Eigen::Index i = 0; i < f.rows(); ++i) face_cuts(v, f, i, h, [&out](const Eigen::Vector3d& p) { out.push_back(p); });
  return out;
}
// The extents of the section y = h within 15 cm of the midline (clear of the T-posed arms near the
// neck): min and max of x, then of z (x0 > x1 where there is none).
std::array<double, 4> neck_section_box(const Vertices& v, double h) {
  std::array<double, 4> box = {1e9, -1e9, 1e9, -1e9};
  for (const auto& p : cut(v, mq::topology().faces, h)) {
    if (std::abs(p.x()) > 0.15) continue;
    box[0] = std::min(box[0], p.x()); box[1] = std::max(box[1], p.x());
    box[2] = std::min(box[2], p.z()); box[3] = std::max(box[3], p.z());
  }
  return box;
}
// The section's front-most (sign +1) or back-most (−1) z among points with |x − x0| ≤ half.
double extreme_z(const std::vector<Eigen::Vector3d>& pts, double x0, double half, int sign) {
  double best = -1e9;
  for (const auto& p : pts)
    if (std::abs(p.x() - x0) <= half) best = std::max(best, sign * p.z());
  return sign * best;
}
// The front-most (sign +1) or back-most (−1) z of the section y = h at exactly x: where the plane
// cuts each triangle in a segment spanning x (through its vertices on the plane, or across its
// edges), interpolated along it (-1e9 · sign where none does).
double section_z_at(const Vertices& v, const Faces& f, double h, double x, int sign) {
  double best = -1e9;
  for (Eigen::Index i = 0; i < f.rows(); ++i) {
    std::array<Eigen::Vector3d, 3> seg;  // a face meets the plane in at most three points
    size_t n = 0;
    face_cuts(v, f, i, h, [&](const Eigen::Vector3d& p) { seg[n++] = p; });
    if (n != 2 || (seg[0].x() - x) * (seg[1].x() - x) > 0 || seg[0].x() == seg[1].x()) continue;
    best = std::max(best, sign * std::lerp(seg[0].z(), seg[1].z(), (x - seg[0].x()) / (seg[1].x() - seg[0].x())));
  }
  return sign * best;
}
// The section's largest x among points in front of / behind z0 by at most `half`.
double extreme_x(const std::vector<Eigen::Vector3d>& pts, double z0, double half, double x_min) {
  double best = -1e9;
  for (const auto& p : pts)
    if (std::abs(p.z() - z0) <= half && p.x() >= x_min) best = std::max(best, p.x());
  return best;
}

// A landmark's position, and a check that records a failure with its value (relief_failures()).
using LandmarkAt = std::function<Eigen::Vector3d(const char*)>;
using Check = std::function<void(bool, const std::string&, double)>;

// The left leg's (x > 0) inner and outer x on the section y = h; nullopt where it has none.
std::optional<std::pair<double, double>> left_leg_span(const Vertices& v, const Faces& f, double h) {
  std::optional<std::pair<double, double>> span;
  for (const auto& p : cut(v, f, h))
    if (p.x() > 0) span = span ? std::pair{std::min(span->first, p.x()), std::max(span->second, p.x())} : std::pair{p.x(), p.x()};
  return span;
}
double span_middle(const std::pair<double, double>& s) { return 0.5 * (s.first + s.second); }

// The lower leg from the front. The calf's inner head bulges past the knee's inner side, and
// below it the leg narrows early: halfway down to the ankle it is narrower than the mean of the
// calf's and the ankle's widths. A lofted leg before 2026-11-28 ran from the knee to the ankle as
// a cone: its calf reached at most 1 mm past the knee, and its mid-shin was wider than that mean.
// The inner sides are compared across the leg's own axis (through the middles of the knee's and
// the ankle's sections), which leans out since the legs stand apart (2026-11-28).
void lower_leg_failures(const Vertices& v, const Faces& f, const LandmarkAt& at, double cm, const Check& check) {
  const double y_knee = at("knee_left").y(), y_calf = at("calf_left").y(), y_ankle = at("ankle_left").y();
  const auto knee = left_leg_span(v, f, y_knee), calf = left_leg_span(v, f, y_calf), ankle = left_leg_span(v, f, y_ankle),
             shin = left_leg_span(v, f, 0.5 * (y_calf + y_ankle));
  if (!knee || !calf || !ankle || !shin) return check(false, "lower leg: a section missed the leg", 0.0);
  auto width = [](const std::pair<double, double>& s) { return s.second - s.first; };
  const double axis_shift = (span_middle(*ankle) - span_middle(*knee)) * (y_calf - y_knee) / (y_ankle - y_knee);  // at the calf
  const double inner = knee->first - (calf->first - axis_shift);
  check(inner >= 0.15 * cm, "calf's inner side beyond the knee's", inner);
  const double narrowing = 0.5 * (width(*calf) + width(*ankle)) - width(*shin);
  check(narrowing >= 0.2 * cm, "shin narrows early below the calf", narrowing);
}

// The heel: the heel landmark is the foot's back-most point (the foot length is taken from it);
// it stands above the sole (≥ 1 cm up) and the heel rounds forward into the sole (2 mm above the
// floor, per 1.70 m, the foot's back is ≥ 5 mm in front of it). The heel before 2026-11-28 fell
// straight to a sole edge, a boot's heel.
void heel_failures(const Vertices& v, const Faces& f, const LandmarkAt& at, double cm, const Check& check) {
  const Eigen::Vector3d h = at("heel_left");
  double foot_back = 1e9;
  for (Eigen::Index i = 0; i < v.rows(); ++i)
    if (v(i, 0) > 0 && v(i, 1) < at("lateral_malleolus_left").y()) foot_back = std::min(foot_back, v(i, 2));
  check(foot_back >= h.z() - 1e-4, "heel landmark at the foot's back", h.z() - foot_back);
  check(h.y() >= 1.0 * cm, "heel's fullest back above the sole", h.y());
  double back = 1e9;
  for (const auto& p : cut(v, f, 0.2 * cm))
    if (p.x() > 0) back = std::min(back, p.z());
  if (back > 1e8) return check(false, "heel: no section 2 mm above the floor", 0.0);
  check(back - h.z() >= 0.5 * cm, "heel rounds into the sole", back - h.z());
}

// The groin: no level groove across the thigh's front where the belly's lowest rings meet it.
// Outward of the thigh's centre, going up from the thigh's girth level to 4 cm above the crotch,
// the front never lies more than 2.5 mm behind both a point below it and a point above it (the
// water the profile would hold; a heavy belly overhanging above holds none). Before 2026-11-28
// the belly's lowest rings held 3 mm on the median checked body and up to 6.5 mm: the hem of a
// pair of shorts.
void groin_failures(const Vertices& v, const Faces& f, const LandmarkAt& at, double cm, const Check& check) {
  const Eigen::Vector3d out_side = at("thigh_left");
  const auto thigh = left_leg_span(v, f, out_side.y());
  if (!thigh) return check(false, "groin: no thigh section", 0.0);
  const double centre = 0.5 * (thigh->first + out_side.x()), x = centre + 0.4 * (out_side.x() - centre);
  std::vector<double> z;  // the front, every 2.5 mm up (levels with no surface at x left out)
  int levels = 0;
  for (double y = out_side.y(); y <= at("crotch").y() + 4 * cm; y += 0.25 * cm, ++levels) {
    const double front = section_z_at(v, f, y, x, +1);
    if (front > -1e8) z.push_back(front);
  }
  const size_t missed = static_cast<size_t>(levels) - z.size();
  if (10 * missed > static_cast<size_t>(levels)) return check(false, "groin: the front missed at " + std::to_string(missed) + " levels", 0.0);
  std::vector<double> below(z.size()), above(z.size());
  for (size_t i = 0; i < z.size(); ++i) below[i] = std::max(z[i], i > 0 ? below[i - 1] : z[i]);
  for (size_t i = z.size(); i-- > 0;) above[i] = std::max(z[i], i + 1 < z.size() ? above[i + 1] : z[i]);
  double groove = 0;
  for (size_t i = 0; i < z.size(); ++i) groove = std::max(groove, std::min(below[i], above[i]) - z[i]);
  check(groove <= 0.25 * cm, "no groove across the thigh's front under the belly", groove);
}

// How far the leg's outer side stands further out than on the thigh's girth section, at most,
// every 5 mm (per 1.70 m) from there down to `bottom` (0 where it never does; −1 without that
// section).
double beyond_thigh_girth(const Vertices& v, const Faces& f, const LandmarkAt& at, double cm, double bottom) {
  const double y_thigh = at("thigh_left").y();
  // Only the faces reaching into [bottom, y_thigh] are cut (the sanitizer's run of the population
  // test took 96 s longer cutting the whole body about 100 times per body).
  std::vector<Eigen::Index> near;
  for (Eigen::Index i = 0; i < f.rows(); ++i) {
    const double lo = std::min({v(f(i, 0), 1), v(f(i, 1), 1), v(f(i, 2), 1)});
    const double hi = std::max({v(f(i, 0), 1), v(f(i, 1), 1), v(f(i, 2), 1)});
    if (hi >= bottom && lo <= y_thigh) near.push_back(i);
  }
  Faces leg(static_cast<Eigen::Index>(near.size()), 3);
  for (size_t i = 0; i < near.size(); ++i) leg.row(static_cast<Eigen::Index>(i)) = f.row(near[i]);
  const auto top = left_leg_span(v, leg, y_thigh - 1e-6);  // the ring's own vertices lie on y_thigh
  if (!top) return -1;
  double out = 0;
  for (double y = y_thigh - 0.5 * cm; y > bottom; y -= 0.5 * cm)
    if (const auto span = left_leg_span(v, leg, y)) out = std::max(out, span->second - top->second);
  return out;
}

// From the front the knee stands under the hip, not out beside it: from the thigh's girth section
// down to 2 cm under the knee the leg's outer side stands at most kKneeBeyondHipMost cm (per
// 1.70 m) further out than on that section, and the population test asks that on at most one
// checked body in a hundred (one in the sanitizer's short run) it stands more than
// kKneeBeyondHip cm further out. The legs' lean carried narrow-hipped men's knees out past it
// (until 2026-12-07 the population test's default run found 92 bodies over 1 cm, and 6 over
// 1.8 cm, up to 2.1 cm); the leg now moves in as far as the calf's inner side lets it, which
// leaves up to 1.5 cm on 4 of 1,021 men checked (every third development man).
constexpr double kKneeBeyondHip = 1.0, kKneeBeyondHipMost = 1.8;
double knee_beyond_hip(const Vertices& v, const Faces& f, const LandmarkAt& at, double cm) {
  return beyond_thigh_girth(v, f, at, cm, at("knee_left").y() - 2 * cm);
}

// From the front and behind, the hip's side runs down into the thigh's without a waist: over the
// thigh's upper half (from its girth section halfway down to the lower thigh's, every 5 mm) the
// leg's outer side never stands more than 1 mm further out than on the girth section. Until
// 2026-12-07 the legs' lean carried the full thigh out past it, by 1.6–9 mm on every fifteenth
// development body (medians 6 mm, women, and 7 mm, men): the outline narrowed at the crotch under
// the hip and widened again below. Below that, the knee (knee_beyond_hip()).
void thigh_outline_failures(const Vertices& v, const Faces& f, const LandmarkAt& at, double cm, const Check& check) {
  const double upper = beyond_thigh_girth(v, f, at, cm, 0.5 * (at("thigh_left").y() + at("lower_thigh_left").y()));
  check(upper >= 0 && upper <= 0.1 * cm, "thigh's side no further out than at its girth", upper);
}

// The back of the neck leans forward from the cervicale (y0) into the nape's hollow under the
// skull, then the skull rounds out behind to the opisthocranion (y1): along the back's midline one
// forward-most point, the back moving only forward below it and only backward above it (within
// 0.2 mm: no roll under the skull, no second hollow), that point at least 1 head-centimetre
// (hu) in front of both ends. Before the nape was drawn (2026-11-28) the back only moved
// backward from C7 up, a straight pipe from the shoulders into the skull. Returns what failed,
// or "".
std::string nape_failure(const Vertices& v, const Faces& f, double y0, double y1, double hu) {
  constexpr double step = 0.002;  // m
  std::vector<double> back;
  for (double y = y0; y <= y1; y += step) back.push_back(extreme_z(cut(v, f, y), 0.0, 0.005, -1));
  const size_t nape = static_cast<size_t>(std::max_element(back.begin(), back.end()) - back.begin());
  const double hollow = back[nape] - std::max(back.front(), back.back());
  if (hollow < hu) return "nape's hollow " + std::to_string(1000 * hollow) + " mm in front of C7 and the occiput";
  for (size_t i = 1; i < back.size(); ++i) {
    const double step = back[i] - back[i - 1];  // > 0: forward, going up
    if (i <= nape ? step < -0.0002 : step > 0.0002)
      return "nape's profile turns back at " + std::to_string(100 * step * static_cast<double>(i)) + " cm above C7";
  }
  return "";
}

// The buttocks meet in a cleft: on the buttock's section (the hip ring, ANSUR's buttock depth and
// girth) and a third of the way down from it toward the gluteal furrow (or 2 cm above the crotch,
// if that is higher), the back's midline lies at least 1 cm (per 1.70 m) in front of the back-most
// point 2.5–9.5 cm beside it (the cheek). Before 2026-11-28 the midline was the buttocks' back-most
// point or within 7 mm of it: one rounded mass. Returns what failed, or "".
std::string cleft_failure(const Vertices& v, const Faces& f, const LandmarkAt& at, double cm) {
  const double y_hip = at("buttock_back").y(), y_low = std::max(at("gluteal_furrow").y(), at("crotch").y() + 2 * cm);
  for (const double y : {y_hip, y_hip - (y_hip - y_low) / 3}) {
    const double midline = section_z_at(v, f, y, 0.0, -1);
    const double cheek = extreme_z(cut(v, f, y), 6.0 * cm, 3.5 * cm, -1);
    if (midline > 1e8 || cheek > 1e8) return "buttocks: no section at " + std::to_string(y) + " m";
    if (midline - cheek < 1.0 * cm)
      return "buttocks' cleft at " + std::to_string(y) + " m only " + std::to_string(1000 * (midline - cheek)) + " mm deep";
  }
  return "";
}

// The relief (generator.cpp, sculpt()) carries a face, a spine, kneecaps and malleoli, measured
// here on the surface itself, in head centimetres (hu) for the face and centimetres scaled by
// stature elsewhere. Each check compares points a lofted ring surface could not tell apart by
// these amounts. Returns the failures' descriptions.
std::vector<std::string> relief_failures(const BodyModel& model, const Vertices& v, const mq::Dimensions& d) {
  std::vector<std::string> out;
  const Faces& f = model.faces();
  const double hu = 0.01 * d.at("headlength") / 0.195, cm = 0.01 * d.at("stature") / 1.70;
  auto at = [&](const char* name) { return Eigen::Vector3d(v.row(model.landmark(name)).transpose()); };
  auto check = [&](bool ok, const std::string& what, double value) {
    if (!ok) out.push_back(what + " (" + std::to_string(value * 1000) + " mm)");
  };
  // Face, from the glabella down (X across, Y below it).
  const Eigen::Vector3d g = at("glabella");
  // The face spans the glabella to the chin ring (generator: 13.06 hu below it, or at least 6 mm
  // above the cervicale where the neck is short); its features' heights scale with it.
  const double chin_y = std::max(d.at("stature") - 23.2 * hu, d.at("cervicaleheight") + 0.006);
  const double face = std::clamp((g.y() - chin_y) / (13.06 * hu), 0.3, 1.0);
  auto face_z = [&](double X, double Y) {
    std::vector<Eigen::Vector3d> front;  // the face: in front of the glabella's plane less 4 hu
    for (const auto& p : cut(v, f, g.y() + Y * face * hu))
      if (p.z() > g.z() - 4 * hu) front.push_back(p);
    return extreme_z(front, X * hu, 0.7 * hu, +1);
  };
  double nose = -1e9;
  for (double Y = -4.6; Y >= -6.0; Y -= 0.2) nose = std::max(nose, face_z(0, Y));
  const double upper_lip = face_z(0, -7.75), eye = face_z(3.2, -2.4), brow = face_z(3.0, -0.6), cheek = face_z(3.2, -4.2);
  check(nose - upper_lip >= 0.6 * hu, "nose tip in front of the upper lip", nose - upper_lip);
  check(nose - eye >= 1.5 * hu, "nose tip in front of the eyes", nose - eye);
  check(brow - eye >= 0.4 * hu, "eye socket behind the brow", brow - eye);
  check(0.5 * (brow + cheek) - eye >= 0.2 * hu, "eye socket behind the line from brow to cheek", 0.5 * (brow + cheek) - eye);
  const double lower_lip = face_z(0, -9.1), fold = face_z(0, -10.3), chin = face_z(0, -11.9);
  check(lower_lip - fold >= 0.15 * hu && chin - fold >= 0.1 * hu,
        "fold between lower lip and chin: lip " + std::to_string((lower_lip - g.z()) / hu) + " fold " + std::to_string((fold - g.z()) / hu) + " chin " + std::to_string((chin - g.z()) / hu),
        std::min(lower_lip - fold, chin - fold));
  // Forehead: the skull rises nearly upright above the brow. Six head-cm above the glabella the
  // forehead's front is at most 1.4 head-cm behind it (a quarter-ellipse dome, an egg, left it
  // about 2 head-cm behind).
  {
    const double forehead = extreme_z(cut(v, f, g.y() + 6 * hu), 0, 0.7 * hu, +1);
    check(g.z() - forehead <= 1.4 * hu, "forehead upright above the brow", g.z() - forehead);
  }
  if (const std::string nape = nape_failure(v, f, at("cervicale").y(), at("opisthocranion").y(), hu); !nape.empty())
    out.push_back(nape);
  // Ears: at ear level the head reaches out to about its breadth at the glabella, its widest
  // (the lofted head is 8 % narrower there).
  {
    const auto pts = cut(v, f, g.y() - 4.3 * face * hu);
    const double cz = 0.5 * (g.z() + at("opisthocranion").z());
    double ear = -1e9;
    for (const auto& p : pts)
      if (p.x() > 0 && p.z() > cz - 3 * hu && p.z() < cz + 1 * hu) ear = std::max(ear, p.x());
    check(ear >= at("head_side_left").x() - 0.2 * hu, "ear stands out", ear - at("head_side_left").x());
    // The ear's back half (the shell's free edge and its rim) stands out from the head at the
    // ear's middle by ≥ 3 mm beyond the head's side just above the ear at the same depth (the
    // head narrows below the brow), and beyond the bowl (concha) in front of it. The shell and
    // hollow before 2026-11-28 stood 0.8–3.7 mm inside that side, and its middle was its fullest.
    const auto middle = cut(v, f, g.y() - 4.6 * face * hu), above = cut(v, f, g.y() - 0.8 * face * hu);
    const double back = extreme_x(middle, cz - 2.1 * hu, 0.5 * hu, 0), bowl = extreme_x(middle, cz - 0.9 * hu, 0.3 * hu, 0);
    const double side = extreme_x(above, cz - 2.1 * hu, 0.5 * hu, 0);
    check(back - side >= 0.3 * hu, "ear's back edge stands out from the head", back - side);
    check(back - bowl >= 0.1 * hu, "ear's bowl behind its back edge", back - bowl);
  }
  // Spine groove between the erector muscles, halfway from the navel to the bust point.
  {
    const double y = 0.5 * (at("omphalion").y() + at("chest_front").y());
    const auto pts = cut(v, f, y);
    double z_lo = 1e9, z_hi = -1e9;
    for (const auto& p : pts) { z_lo = std::min(z_lo, p.z()); z_hi = std::max(z_hi, p.z()); }
    std::vector<Eigen::Vector3d> back;  // the section's back half
    for (const auto& p : pts)
      if (p.z() < 0.5 * (z_lo + z_hi)) back.push_back(p);
    double spine = 1e9, beside = 1e9;  // back-most z on the midline / 2–5 cm to either side
    for (const auto& p : back) {
      if (std::abs(p.x()) <= 1.0 * cm) spine = std::min(spine, p.z());
      if (std::abs(p.x()) >= 2.0 * cm && std::abs(p.x()) <= 5.0 * cm) beside = std::min(beside, p.z());
    }
    check(spine - beside >= 0.3 * cm, "spine groove at y " + std::to_string(y) + " (" + std::to_string(pts.size()) + " section points)", spine - beside);
  }
  // Kneecap: the knee's front stands out of the line from 7 cm above it to 7 cm below it.
  {
    const Eigen::Vector3d k = at("knee_left");
    auto front = [&](double dy) { return extreme_z(cut(v, f, k.y() + dy), k.x(), 1.0 * cm, +1); };
    const double bump = front(0.6 * cm) - 0.5 * (front(7.6 * cm) + front(-6.4 * cm));
    check(bump >= 0.3 * cm, "kneecap", bump);
  }
  // Lateral malleolus: the ankle's outer side stands out of the side 2.5 cm above and 2 cm below it.
  {
    const Eigen::Vector3d m = at("lateral_malleolus_left");
    auto side = [&](double dy) { return extreme_x(cut(v, f, m.y() + dy), m.z(), 1.0 * cm, 0); };
    const double bump = side(0) - 0.5 * (side(2.5 * cm) + side(-2.0 * cm));
    check(bump >= 0.2 * cm, "lateral malleolus", bump);
  }
  lower_leg_failures(v, f, at, cm, check);
  heel_failures(v, f, at, cm, check);
  groin_failures(v, f, at, cm, check);
  thigh_outline_failures(v, f, at, cm, check);
  if (const std::string cleft = cleft_failure(v, f, at, cm); !cleft.empty()) out.push_back(cleft);
  return out;
}
}  // namespace

TEST(MannequinGenerator, TopologyIsClosedManifoldAndOriented) {
  const auto& topo = mq::topology();
  EXPECT_GE(topo.vertex_count, 10000);
  EXPECT_LE(topo.vertex_count, 25000);
  const MeshCheck c = check_mesh(topo.faces, topo.vertex_count);
  EXPECT_TRUE(c.closed);
  EXPECT_TRUE(c.manifold);
  EXPECT_TRUE(c.consistently_oriented);
  EXPECT_EQ(c.unused_vertices, 0);
  EXPECT_EQ(c.degenerate_faces, 0);
  // Euler characteristic of a sphere: the body has no handles.
  EXPECT_EQ(topo.vertex_count - topo.faces.rows() / 2, 2);
}

TEST(MannequinGenerator, EveryBodyHasTheSameVertexCountAndPositiveVolume) {
  const auto& topo = mq::topology();
  for (const auto& [dims, sex] : sample_bodies()) {
    const Vertices v = mq::generate(dims, sex);
    ASSERT_EQ(v.rows(), topo.vertex_count);
    EXPECT_TRUE(v.allFinite());
    EXPECT_GT(signed_volume(v, topo.faces), 0.02);
    EXPECT_NEAR(v.col(1).minCoeff(), 0.0, 1e-12);  // feet on the floor
    EXPECT_NEAR(v.col(1).maxCoeff(), dims.at("stature"), 1e-9);
  }
}

TEST(MannequinGenerator, DeterministicOutput) {
  const auto d = mq::typical_dimensions(Sex::Female);
  EXPECT_EQ(mq::generate(d, Sex::Female), mq::generate(d, Sex::Female));
}

// The committed models must rebuild bit for bit on other x86-64 machines (scripts/build-models.sh). Eigen
// sizes a matrix product's blocks by the CPU caches it detects, and the blocks set the order the
// sums are added in: the PCA must not depend on them. Two "machines" here: the same bodies with
// Eigen told of small caches, then of large ones.
TEST(Population, PrincipalComponentsDoNotDependOnTheCpuCaches) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd bodies(400, 3000);
  for (Eigen::Index c = 0; c < bodies.cols(); ++c)
    for (Eigen::Index r = 0; r < bodies.rows(); ++r) bodies(r, c) = normal(rng) * (1.0 + 50.0 / (1 + c % 37));
  struct Restore {  // this test's own changes to Eigen's sizes, undone however it ends
    std::ptrdiff_t l1 = Eigen::l1CacheSize(), l2 = Eigen::l2CacheSize(), l3 = Eigen::l3CacheSize();
    ~Restore() { Eigen::setCpuCacheSizes(l1, l2, l3); }
  } restore;
  auto pca_with_caches = [&](std::ptrdiff_t c1, std::ptrdiff_t c2, std::ptrdiff_t c3) {
    Eigen::setCpuCacheSizes(c1, c2, c3);
    Eigen::MatrixXd copy = bodies;
    const mannequin::PrincipalComponents pca = mannequin::principal_components(copy, 6, 11);
    // principal_components puts back the sizes it was called with.
    EXPECT_EQ(Eigen::l1CacheSize(), c1);
    EXPECT_EQ(Eigen::l2CacheSize(), c2);
    EXPECT_EQ(Eigen::l3CacheSize(), c3);
    return pca;
  };
  const auto small = pca_with_caches(8 * 1024, 64 * 1024, 512 * 1024);
  const auto large = pca_with_caches(64 * 1024, 4 * 1024 * 1024, 64 * 1024 * 1024);
  EXPECT_TRUE(small.mean == large.mean);
  EXPECT_TRUE(small.directions == large.directions) << "largest difference "
                                                     << (small.directions - large.directions).cwiseAbs().maxCoeff();
  EXPECT_EQ(small.explained, large.explained);
}

TEST(MannequinGenerator, LandmarksAreMirrorSymmetric) {
  const auto& topo = mq::topology();
  const Vertices v = mq::generate(mq::typical_dimensions(Sex::Male), Sex::Male);
  int pairs = 0;
  for (const auto& [name, idx] : topo.landmarks) {
    const auto pos = name.rfind("_left");
    if (pos == std::string::npos || pos + 5 != name.size()) continue;
    const std::string right = name.substr(0, pos) + "_right";
    ASSERT_TRUE(topo.landmarks.count(right)) << right;
    const int r = topo.landmarks.at(right);
    EXPECT_NEAR(v(idx, 0), -v(r, 0), 1e-9) << name;
    EXPECT_NEAR(v(idx, 1), v(r, 1), 1e-9) << name;
    EXPECT_NEAR(v(idx, 2), v(r, 2), 1e-9) << name;
    EXPECT_GT(v(idx, 0), 0) << name << " should be on the body's left (+X)";
    ++pairs;
  }
  EXPECT_GT(pairs, 20);
}

TEST(MannequinGenerator, HeightsAreOrdered) {
  const auto& lm = mq::topology().landmarks;
  for (const auto& [dims, sex] : sample_bodies()) {
    const Vertices v = mq::generate(dims, sex);
    auto y = [&](const char* n) { return v(lm.at(n), 1); };
    EXPECT_LT(y("ankle_left"), y("knee_left"));
    EXPECT_LT(y("knee_left"), y("crotch"));
    EXPECT_LT(y("crotch"), y("omphalion"));
    EXPECT_LT(y("omphalion"), y("chest_front"));
    EXPECT_LT(y("chest_front"), y("acromion_left"));
    EXPECT_LT(y("acromion_left"), y("vertex"));
    EXPECT_GT(v(lm.at("toe_left"), 2), v(lm.at("heel_left"), 2));  // feet point forward (+Z)
    EXPECT_GT(v(lm.at("glabella"), 2), v(lm.at("opisthocranion"), 2));
  }
}

TEST(MannequinGenerator, RigWeightsAreConvexAndSparse) {
  const auto& topo = mq::topology();
  ASSERT_EQ(topo.joint_regressor.rows(), 54);
  ASSERT_EQ(topo.skin_weights.rows(), topo.vertex_count);
  for (int j = 0; j < 54; ++j) {
    double sum = 0;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(topo.joint_regressor, j); it; ++it) {
      EXPECT_GE(it.value(), 0);
      sum += it.value();
    }
    EXPECT_NEAR(sum, 1.0, 1e-9) << rig_joint_names()[static_cast<size_t>(j)];
  }
  for (int i = 0; i < topo.vertex_count; ++i) {
    double sum = 0;
    int nnz = 0;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(topo.skin_weights, i); it; ++it) {
      EXPECT_GE(it.value(), 0);
      sum += it.value();
      ++nnz;
    }
    ASSERT_NEAR(sum, 1.0, 1e-9) << "vertex " << i;
    ASSERT_LE(nnz, 4);
  }
}

TEST(MannequinGenerator, JointsLieWhereAnatomyPutsThem) {
  const Vertices v = mq::generate(mq::typical_dimensions(Sex::Male), Sex::Male);
  const BodyModel model = model_for(v, Sex::Male);
  const Eigen::MatrixX3d j = model.joints(v);
  const auto& lm = mq::topology().landmarks;
  // Knees between ankles and hips; elbows between shoulders and wrists; left joints on +X.
  EXPECT_LT(j(7, 1), j(4, 1));
  EXPECT_LT(j(4, 1), j(1, 1));
  EXPECT_LT(j(16, 0), j(18, 0));
  EXPECT_LT(j(18, 0), j(20, 0));
  EXPECT_GT(j(1, 0), 0);
  EXPECT_LT(j(2, 0), 0);
  EXPECT_GT(j(15, 1), j(12, 1));
  // The elbow joint sits inside the arm near the radiale.
  EXPECT_NEAR(j(18, 0), v(lm.at("radiale_left"), 0), 0.02);
}

TEST(MannequinGenerator, BendingElbowAndKneeDoesNotExplode) {
  const Vertices v = mq::generate(mq::typical_dimensions(Sex::Female), Sex::Female);
  const BodyModel model = model_for(v, Sex::Female);
  for (int joint : {18, 4}) {  // left elbow, left knee
    Pose pose = zero_pose(model);
    pose(joint, joint == 18 ? 1 : 0) = M_PI / 2;
    const Vertices posed = pose_vertices(model, v, pose);
    ASSERT_TRUE(posed.allFinite());
    const double moved = (posed - v).rowwise().norm().maxCoeff();
    // Nothing travels farther than a forearm+hand (or shank+foot) swinging through 90°.
    EXPECT_GT(moved, 0.1);
    EXPECT_LT(moved, 0.75);
    // Vertices far from the bent joint do not move.
    const int head = mq::topology().landmarks.at("vertex");
    EXPECT_LT((posed.row(head) - v.row(head)).norm(), 1e-9);
  }
}

// The hand has five digits with SMPL-H's three joints each: separate fingers in order
// from the thumb's side, each joint bending its own finger from that joint on and nothing else.
int joint_named(const BodyModel& model, const std::string& name) {
  const auto& names = model.data().joint_names;
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : static_cast<int>(it - names.begin());
}

TEST(MannequinGenerator, RigHasSmplJointsThenSmplhFingers) {
  const Vertices v = mq::generate(mq::typical_dimensions(Sex::Female), Sex::Female);
  const BodyModel model = model_for(v, Sex::Female);
  ASSERT_EQ(model.joint_count(), 54);
  for (int j = 0; j < 24; ++j) EXPECT_EQ(model.data().joint_names[static_cast<size_t>(j)], smpl_joint_names()[static_cast<size_t>(j)]);
  EXPECT_EQ(model.data().joint_names[24], "left_index1");
  EXPECT_EQ(model.data().joint_names[38], "left_thumb3");
  EXPECT_EQ(model.data().joint_names[53], "right_thumb3");
  // Each finger's chain hangs from the hand joint of its side.
  EXPECT_EQ(model.data().parents[static_cast<size_t>(joint_named(model, "left_middle1"))], joint_named(model, "left_hand"));
  EXPECT_EQ(model.data().parents[static_cast<size_t>(joint_named(model, "right_thumb1"))], joint_named(model, "right_hand"));
  EXPECT_EQ(model.data().parents[static_cast<size_t>(joint_named(model, "left_ring3"))], joint_named(model, "left_ring2"));
}

TEST(MannequinGenerator, FingersAreSeparateAndInAnatomicalOrder) {
  for (Sex sex : {Sex::Female, Sex::Male}) {
    const Vertices v = mq::generate(mq::typical_dimensions(sex), sex);
    const BodyModel model = model_for(v, sex);
    ASSERT_EQ(model.joint_count(), 54);
    const Eigen::MatrixX3d j = model.joints(v);
    auto at = [&](const std::string& name) -> Eigen::Vector3d { return j.row(joint_named(model, name)).transpose(); };
    for (const char* side : {"left_", "right_"}) {
      const std::string s = side;
      // Knuckle to last joint runs out along the arm (±X) on every finger.
      const double out = s == "left_" ? 1 : -1;
      for (const char* f : {"index", "middle", "ring", "pinky", "thumb"}) {
        EXPECT_GT(out * (at(s + f + "2").x() - at(s + f + "1").x()), 0.01) << s << f;
        EXPECT_GT(out * (at(s + f + "3").x() - at(s + f + "2").x()), 0.01) << s << f;
      }
      // Index to little finger from the front (+Z, the thumb's side) backwards, at least a
      // centimetre apart at the last joints: the fingers are separate, not a mitten.
      const char* order[] = {"thumb", "index", "middle", "ring", "pinky"};
      for (int k = 0; k + 1 < 5; ++k)
        EXPECT_GT(at(s + order[k] + "3").z() - at(s + order[k + 1] + "3").z(), 0.01) << s << order[k];
      // The middle fingertip is the dactylion, past every other digit.
      const double tip = v(mq::topology().landmarks.at("dactylion_" + s.substr(0, s.size() - 1)), 0);
      for (const char* f : {"index", "ring", "pinky", "thumb"}) EXPECT_GT(out * (tip - at(s + f + "3").x()), 0.0) << s << f;
      // The knuckles lie on an arc: the little finger's at least 7 mm behind the middle finger's
      // (per 19 cm of hand), the ring finger's behind it too, and the index's no further back
      // than the ring finger's. A straight knuckle ring (before 2026-11-28) put all four level.
      const double per_hand = mq::typical_dimensions(sex).at("handlength") / 0.19;
      auto behind = [&](const char* f) { return out * (at(s + "middle1").x() - at(s + f + "1").x()) / per_hand; };
      EXPECT_GT(behind("pinky"), 0.007) << s;
      EXPECT_GT(behind("ring"), 0.001) << s;
      EXPECT_LT(behind("index"), behind("ring")) << s;
      EXPECT_LT(behind("ring"), behind("pinky")) << s;
    }
  }
}

// The knuckles rise on the back of the hand (+Y, palm down): over the middle finger's knuckle
// joint the hand's top stands at least 1 mm (per 19 cm of hand) above its top halfway to the ring
// finger's. Without the knuckles' rise (before 2026-11-28) the hand's top is smooth there and fails this.
TEST(MannequinGenerator, KnucklesRiseOnTheBackOfTheHand) {
  for (Sex sex : {Sex::Female, Sex::Male}) {
    const Vertices v = mq::generate(mq::typical_dimensions(sex), sex);
    const BodyModel model = model_for(v, sex);
    const Eigen::MatrixX3d j = model.joints(v);
    const Eigen::Vector3d middle = j.row(joint_named(model, "left_middle1")).transpose(),
                          ring = j.row(joint_named(model, "left_ring1")).transpose();
    auto top_at = [&](double z) {  // the hand's top over the middle finger's knuckle, at depth z
      double top = -1e9;
      for (Eigen::Index i = 0; i < v.rows(); ++i)
        if (std::abs(v(i, 0) - middle.x()) < 0.003 && std::abs(v(i, 2) - z) < 0.0035 && std::abs(v(i, 1) - middle.y()) < 0.03)
          top = std::max(top, v(i, 1));
      return top;
    };
    const double per_hand = mq::typical_dimensions(sex).at("handlength") / 0.19;
    EXPECT_GT((top_at(middle.z()) - top_at(0.5 * (middle.z() + ring.z()))) / per_hand, 0.001) << to_string(sex);
  }
}

// Five separate toes on each foot, the big toe on the inside and the broadest: some vertical
// section across the front of the foot (between 70 % of the foot's length from the heel and the
// big toe's tip) cuts it into five separate loops, the most medial the widest. Bodies from the
// smallest to the largest feet.
TEST(MannequinGenerator, FeetHaveFiveSeparateToes) {
  for (Sex sex : {Sex::Female, Sex::Male})
    for (double scale : {0.85, 1.0, 1.15}) {
      mq::Dimensions d = mq::typical_dimensions(sex);
      d.at("footlength") *= scale;
      d.at("footbreadthhorizontal") *= scale;
      const Vertices v = mq::generate(d, sex);
      const auto& lm = mq::topology().landmarks;
      for (const char* side : {"left", "right"}) {
        const std::string s = side;
        const Eigen::Vector3d heel = v.row(lm.at("heel_" + s)).transpose(), toe = v.row(lm.at("toe_" + s)).transpose();
        const double length = (toe - heel).norm(), out = s == "left" ? 1 : -1;
        std::vector<std::pair<double, double>> best;  // (distance from the body's midline, width) per loop
        for (double f = 0.7; f < 1.0; f += 0.005) {
          std::vector<std::pair<double, double>> loops;
          for (const auto& loop : plane_section(v, mq::topology().faces, Eigen::Vector3d(0, 0, heel.z() + f * length),
                                                Eigen::Vector3d::UnitZ())) {
            double lo = 1e9, hi = -1e9, top = -1e9;
            for (const auto& p : loop) lo = std::min(lo, out * p.x()), hi = std::max(hi, out * p.x()), top = std::max(top, p.y());
            if (top < 0.08 && lo > 0) loops.push_back({0.5 * (lo + hi), hi - lo});  // this foot's
          }
          if (loops.size() > best.size()) best = loops;
        }
        ASSERT_EQ(best.size(), 5u) << to_string(sex) << " × " << scale << ", " << s << " foot";
        std::sort(best.begin(), best.end());
        for (size_t t = 1; t < 5; ++t) EXPECT_GT(best[0].second, best[t].second) << "the big toe is the broadest";
      }
    }
}

// The toes bend at the ball of the foot (SMPL's foot joint): turning it up lifts the big toe's
// tip and leaves the heel and the other foot where they were.
TEST(MannequinGenerator, ToesBendAtTheBallOfTheFoot) {
  const Vertices v = mq::generate(mq::typical_dimensions(Sex::Female), Sex::Female);
  const BodyModel model = model_for(v, Sex::Female);
  Pose pose = zero_pose(model);
  pose(joint_named(model, "left_foot"), 0) = -0.5;  // about +X: the toes (+Z) go up
  const Vertices posed = pose_vertices(model, v, pose);
  const auto& lm = mq::topology().landmarks;
  EXPECT_GT(posed(lm.at("toe_left"), 1) - v(lm.at("toe_left"), 1), 0.01);
  EXPECT_LT((posed.row(lm.at("heel_left")) - v.row(lm.at("heel_left"))).norm(), 1e-9);
  EXPECT_LT((posed.row(lm.at("toe_right")) - v.row(lm.at("toe_right"))).norm(), 1e-9);
  EXPECT_TRUE(self_intersections(posed, mq::topology().faces, 1).empty());
}

TEST(MannequinGenerator, EachFingerJointBendsOnlyItsFinger) {
  const Vertices v = mq::generate(mq::typical_dimensions(Sex::Male), Sex::Male);
  const BodyModel model = model_for(v, Sex::Male);
  const Eigen::MatrixX3d j = model.joints(v);
  const int middle_tip = mq::topology().landmarks.at("dactylion_left");
  for (const char* f : {"index", "middle", "ring", "pinky"})
    for (int k = 1; k <= 3; ++k) {
      const std::string name = std::string("left_") + f + std::to_string(k);
      Pose pose = zero_pose(model);
      pose(joint_named(model, name), 2) = -M_PI / 2;  // flex towards the palm (−Y)
      const Vertices posed = pose_vertices(model, v, pose);
      ASSERT_TRUE(posed.allFinite());
      const Eigen::VectorXd moved = (posed - v).rowwise().norm();
      // Something moves, by no more than the finger's length swinging through 90°, all of it
      // beyond the bent joint (less the skinning's blend band), and what moves most (the tip)
      // goes down towards the palm, not up.
      const double joint_x = j(joint_named(model, name), 0);
      Eigen::Index farthest = 0;
      EXPECT_GT(moved.maxCoeff(&farthest), 0.005) << name;
      EXPECT_LT(moved.maxCoeff(), 0.15) << name;
      EXPECT_LT(posed(farthest, 1), v(farthest, 1) - 0.004) << name;
      for (Eigen::Index i = 0; i < v.rows(); ++i) {
        if (moved(i) > 1e-4) {
          EXPECT_GT(v(i, 0), joint_x - 0.02) << name << " moved vertex " << i;
        }
      }
      // Bending another finger leaves the middle fingertip where it was.
      if (std::string(f) != "middle") {
        EXPECT_LT(moved(middle_tip), 1e-9) << name;
      } else {
        EXPECT_GT(moved(middle_tip), 0.01) << name;
      }
    }
}

TEST(MannequinGenerator, FistPoseClosesBothHands) {
  const Vertices v = mq::generate(mq::typical_dimensions(Sex::Female), Sex::Female);
  const BodyModel model = model_for(v, Sex::Female);
  const Vertices posed = pose_vertices(model, v, fist_pose(model));
  ASSERT_TRUE(posed.allFinite());
  const Eigen::MatrixX3d j = model.joints(v);
  for (const char* side : {"left", "right"}) {
    const Eigen::Vector3d wrist = j.row(joint_named(model, std::string(side) + "_wrist")).transpose();
    const int tip = mq::topology().landmarks.at(std::string("dactylion_") + side);
    // The middle fingertip comes back towards the wrist (a closed hand is shorter than an open
    // one by well over a third) and ends below the back of the hand.
    const double open = (v.row(tip).transpose() - wrist).norm(), closed = (posed.row(tip).transpose() - wrist).norm();
    EXPECT_LT(closed, 0.65 * open) << side;
    EXPECT_LT(posed(tip, 1), v(tip, 1) - 0.01) << side;
    // The thumb is opposed, lying across the fingers: its last segment is under the palm (below
    // the index knuckle) and has crossed the index finger towards the little finger (the fingers
    // run from index at +Z to little at −Z on both hands).
    const int thumb3 = joint_named(model, std::string(side) + "_thumb3");
    const Eigen::Vector3d index1 = j.row(joint_named(model, std::string(side) + "_index1")).transpose();
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
    for (int i = 0; i < posed.rows(); ++i)
      if (mq::topology().skin_weights.coeff(i, thumb3) > 0.5) { sum += posed.row(i).transpose(); ++n; }
    ASSERT_GT(n, 0) << side;
    const Eigen::Vector3d end = sum / n;
    EXPECT_LT(end.y(), index1.y() - 0.01) << side << ": thumb's end under the palm";
    EXPECT_LT(end.z(), index1.z()) << side << ": thumb's end across the index finger";
  }
  // Nothing but the hands moves.
  EXPECT_LT((posed.row(mq::topology().landmarks.at("vertex")) - v.row(mq::topology().landmarks.at("vertex"))).norm(), 1e-12);
  EXPECT_LT((posed.row(mq::topology().landmarks.at("stylion_left")) - v.row(mq::topology().landmarks.at("stylion_left"))).norm(), 1e-12);
}

// Skinning keeps the body's volume when the shoulders, elbows, knees, wrists and fingers bend
// (linear blend skinning loses volume where it collapses a joint or twists it into a candy
// wrapper): arms lowered to an A-pose, raised overhead, mid-stride and fists, within 1 % on both
// sexes' typical bodies.
TEST(MannequinGenerator, PosesKeepTheBodysVolume) {
  for (Sex sex : {Sex::Female, Sex::Male}) {
    const Vertices v = mq::generate(mq::typical_dimensions(sex), sex);
    const BodyModel model = model_for(v, sex);
    const double rest = signed_volume(v, mq::topology().faces);
    Pose overhead = zero_pose(model);
    overhead(joint_named(model, "left_shoulder"), 2) = 1.3;
    overhead(joint_named(model, "right_shoulder"), 2) = -1.3;
    Pose wrists = a_pose(model);
    wrists(joint_named(model, "left_wrist"), 2) = -0.8;
    wrists(joint_named(model, "right_wrist"), 1) = 0.8;
    const std::pair<const char*, Pose> poses[] = {{"a", a_pose(model)}, {"overhead", overhead}, {"stride", stride_pose(model)},
                                                  {"fist", fist_pose(model)}, {"wrists", wrists}};
    for (const auto& [name, pose] : poses) {
      const double posed = signed_volume(pose_vertices(model, v, pose), mq::topology().faces);
      EXPECT_NEAR(posed / rest, 1.0, 0.01) << name << " " << to_string(sex);
    }
  }
}

// The shoulders bend without folding the skin through itself: arms lowered to an A-pose and
// raised 60° above the horizontal leave no face crossing another, and no edge of the arms (the
// shoulder and armpit included) folds by more than 120° (70° in the A-pose). With the chains'
// weights alone (before smooth_shoulder_weights) the typical man's raised armpit folds by 180° and
// crosses itself; before the armpit's folds were filled (fair()) his A-posed arm folded by 82°.
TEST(MannequinGenerator, ShouldersBendWithoutFolding) {
  for (Sex sex : {Sex::Female, Sex::Male}) {
    const Vertices v = mq::generate(mq::typical_dimensions(sex), sex);
    const BodyModel model = model_for(v, sex);
    const auto regions = vertex_regions(mq::topology().skin_weights, rig_joint_names());
    for (double degrees : {45.0, -60.0}) {
      const Vertices posed = pose_vertices(model, v, a_pose(model, degrees));
      EXPECT_TRUE(self_intersections(posed, mq::topology().faces, 1).empty()) << to_string(sex) << " " << degrees << "°";
      for (const auto& r : crease_report(posed, mq::topology().faces, regions)) {
        if (r.region == BodyRegion::Arms) {
          EXPECT_LT(r.max_degrees, degrees > 0 ? 70 : 120) << to_string(sex) << " " << degrees << "°";
        }
      }
    }
  }
}

// The neck's front leans forward up to the floor of the mouth. On the midline, at C7's height
// (between the neck's girth and the chin), the front stands at least 8 % of the way from the
// neck's front to the chin's (the chin: the first front-most point going up from C7, where the
// front turns back again). With the front at C7's height at the neck's own (before 2026-11-28)
// the neck stood upright to a level shelf under a sharp-edged chin: 2 % on all five bodies
// (22–26 % now).
TEST(MannequinGenerator, NecksFrontLeansUpToTheJaw) {
  for (const auto& [d, sex] : sample_bodies()) {
    const Vertices v = mq::generate(d, sex);
    const auto& lm = mq::topology().landmarks;
    const Faces& f = mq::topology().faces;
    const double cm = 0.01 * d.at("stature") / 1.70;
    const double y_neck = v(lm.at("neck_front"), 1), y_c7 = v(lm.at("cervicale"), 1);
    ASSERT_LT(y_neck, y_c7) << to_string(sex);
    const double neck = section_z_at(v, f, y_neck, 0.0, +1), at_c7 = section_z_at(v, f, y_c7, 0.0, +1);
    double chin = at_c7;
    for (double y = y_c7; y <= y_c7 + 8 * cm; y += 0.1 * cm) {
      const double z = section_z_at(v, f, y, 0.0, +1);
      if (z < chin - 0.2 * cm) break;  // past the chin's front, turning back under the lip
      chin = std::max(chin, z);
    }
    ASSERT_GT(chin, neck + 3 * cm) << to_string(sex) << ": no chin in front of the neck";
    EXPECT_GE((at_c7 - neck) / (chin - neck), 0.08) << to_string(sex) << ", " << d.at("stature") << " m tall";
  }
}

// The face around the eyes is drawn on a grid fine enough for the lids: within the box from 2
// to 4.2 head-cm either side of the midline and 1.8 to 3.6 head-cm under the glabella (a head-cm
// is 1/19.5 of the head's length), there are at least 120 triangles on each side, no edge is
// longer than 0.5 head-cm, and the two eyes' triangles are mirror images of each other, so a
// lid's margin slanting across the grid is cut the same way on both. (The box stops short of the
// eyes' corners, 1.65 and 4.55 head-cm out, where the face's columns widen toward the side.) Before the face's fine
// rings (2026-11-29) the box held about 50 (now 170–180), with edges up to 0.68 head-cm, and every
// quad was cut along the same diagonal on both sides.
TEST(MannequinGenerator, EyesHaveAFineSymmetricGrid) {
  const Faces& f = mq::topology().faces;
  for (const auto& [d, sex] : sample_bodies()) {
    const Vertices v = mq::generate(d, sex);
    const double hu = 0.01 * d.at("headlength") / 0.195, y_g = v(mq::topology().landmarks.at("glabella"), 1);
    // The face's side of the head: more than 10 head-cm in front of its back.
    const double z_face = v(mq::topology().landmarks.at("opisthocranion"), 2) + 10 * hu;
    auto in_box = [&](int i) {
      const double ax = std::abs(v(i, 0)), below = (y_g - v(i, 1)) / hu;
      return ax >= 2.0 * hu && ax <= 4.2 * hu && below >= 1.8 && below <= 3.6 && v(i, 2) > z_face;
    };
    std::map<std::array<double, 3>, int> at;  // vertex by position, to find each one's mirror image
    for (Eigen::Index i = 0; i < v.rows(); ++i) at[{v(i, 0), v(i, 1), v(i, 2)}] = static_cast<int>(i);
    std::set<std::array<int, 3>> left, right_mirrored;
    double longest = 0;
    for (Eigen::Index r = 0; r < f.rows(); ++r) {
      if (!in_box(f(r, 0)) || !in_box(f(r, 1)) || !in_box(f(r, 2))) continue;
      for (int c = 0; c < 3; ++c) longest = std::max(longest, (v.row(f(r, c)) - v.row(f(r, (c + 1) % 3))).norm());
      std::array<int, 3> t{f(r, 0), f(r, 1), f(r, 2)};
      if (v(t[0], 0) > 0) {
        std::sort(t.begin(), t.end());
        left.insert(t);
        continue;
      }
      for (int& id : t) {
        const auto m = at.find({-v(id, 0), v(id, 1), v(id, 2)});
        id = m == at.end() ? -1 : m->second;
      }
      std::sort(t.begin(), t.end());
      right_mirrored.insert(t);
    }
    const std::string who = std::string(to_string(sex)) + ", " + std::to_string(d.at("stature")) + " m tall";
    EXPECT_GE(left.size(), 120u) << who;
    EXPECT_LE(longest, 0.5 * hu) << who;
    EXPECT_EQ(left, right_mirrored) << who;
  }
}

// The neck leans forward, so a level section through it is at least as deep as it is wide: at the
// neck's girth level the section (within 15 cm of the midline, clear of the T-posed arms) is no
// wider than it is deep. With the girth's ring 12 % wider than a circle and 6 % shallower (until
// the evening of 2026-11-29) it was about a fifth wider than deep on every sample body, and from
// the front the neck was a broad column under a jaw as wide as it.
TEST(MannequinGenerator, NeckIsNoWiderThanDeepAtItsGirth) {
  for (const auto& [d, sex] : sample_bodies()) {
    const Vertices v = mq::generate(d, sex);
    const double y = v(mq::topology().landmarks.at("neck_front"), 1);
    const auto [x0, x1, z0, z1] = neck_section_box(v, y);
    ASSERT_LT(x0, x1) << to_string(sex) << ": no section at the neck's girth";
    EXPECT_LE(x1 - x0, z1 - z0) << to_string(sex) << ", " << d.at("stature") << " m: " << (x1 - x0) * 100 << " cm wide, "
                                << (z1 - z0) * 100 << " cm deep";
  }
}

// The neck flows into the trapezius: the shoulder line starts rising into the neck's side just
// under C7, so 2.5 cm (per 1.70 m) under C7 the level section (within 15 cm of the midline, clear
// of the T-posed arms) is at least 1.16 times as wide as at the neck's girth (1.22–1.46 on the
// sample bodies; the level follows C7 and lies only 0.8 cm under the girth's on the men, so their
// margin is small). With the girth's ring 2.6 cm under the chin and the trapezius' upper ring a
// quarter of the way out from the neck (until 2026-12-07) it was 1.01–1.12 times as wide: a
// column of neck from the jaw down to flat shoulders, from the front and from behind.
TEST(MannequinGenerator, NeckFlowsIntoTheTrapezius) {
  for (const auto& [d, sex] : sample_bodies()) {
    const Vertices v = mq::generate(d, sex);
    const auto& lm = mq::topology().landmarks;
    auto width = [&](double y) {
      const auto box = neck_section_box(v, y);
      return box[1] - box[0];
    };
    const double cm = 0.01 * d.at("stature") / 1.70;
    const double girth_level = width(v(lm.at("neck_front"), 1)), under_c7 = width(v(lm.at("cervicale"), 1) - 2.5 * cm);
    ASSERT_GT(girth_level, 0.05) << to_string(sex) << ": no section at the neck's girth";
    EXPECT_GE(under_c7 / girth_level, 1.16) << to_string(sex) << ", " << d.at("stature") << " m: " << under_c7 * 100
                                            << " cm wide 2.5 cm under C7, " << girth_level * 100 << " at the girth";
  }
}

TEST(MannequinGenerator, NapeHollowsUnderTheSkull) {
  for (const auto& [d, sex] : sample_bodies()) {
    const Vertices v = mq::generate(d, sex);
    const auto& lm = mq::topology().landmarks;
    const double y0 = v(lm.at("cervicale"), 1), y1 = v(lm.at("opisthocranion"), 1);
    ASSERT_LT(y0 + 0.05, y1) << to_string(sex);
    EXPECT_EQ(nape_failure(v, mq::topology().faces, y0, y1, 0.01 * d.at("headlength") / 0.195), "") << to_string(sex) << ", " << d.at("stature") << " m tall";
  }
}

// The back of the head curves smoothly from the nape up over the glabella ring: along the back's
// midline (its vertices, one per ring, from 11 head-cm under the opisthocranion, below the nape's
// hollow, to 3 over it) no vertex's curvature stands more than 3°/head-cm off the mean of its
// neighbours', and just over the glabella ring (which carries the opisthocranion) the curvature is
// within 3°/head-cm of just under it. Before 2026-11-29 the nose ring's back was a kink (27–37°/head-cm off on these
// bodies) and the dome started flat over the glabella ring (3.2–4.3°/head-cm less curved than
// the head under it): a band across the back of the head at each.
TEST(MannequinGenerator, BackOfTheHeadCurvesSmoothly) {
  for (const auto& [d, sex] : sample_bodies()) {
    const Vertices v = mq::generate(d, sex);
    const auto& lm = mq::topology().landmarks;
    const double hu = 0.01 * d.at("headlength") / 0.195;
    const Eigen::Vector3d back = v.row(lm.at("opisthocranion")), front = v.row(lm.at("glabella"));
    std::vector<Eigen::Vector2d> profile;  // (y, z) of the back midline's vertices, upward
    for (Eigen::Index i = 0; i < v.rows(); ++i)
      if (v(i, 0) == 0.0 && v(i, 2) < 0.5 * (back.z() + front.z()) && std::abs(v(i, 1) - back.y() + 4 * hu) < 7 * hu)
        profile.emplace_back(v(i, 1), v(i, 2));
    std::sort(profile.begin(), profile.end(), [](const auto& a, const auto& b) { return a.x() < b.x(); });
    ASSERT_GE(profile.size(), 20u) << to_string(sex);
    std::vector<double> curvature(profile.size(), 0.0);  // degrees per head-cm, at each vertex
    size_t glabella_ring = 0;
    for (size_t i = 1; i + 1 < profile.size(); ++i) {
      const Eigen::Vector2d a = profile[i] - profile[i - 1], b = profile[i + 1] - profile[i];
      const double turn = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b)) * 180 / std::numbers::pi;
      curvature[i] = turn / (0.5 * (a.norm() + b.norm()) / hu);
      if (std::abs(profile[i].x() - back.y()) < 1e-9) glabella_ring = i;
    }
    for (size_t i = 2; i + 2 < profile.size(); ++i)
      EXPECT_LE(std::abs(curvature[i] - 0.5 * (curvature[i - 1] + curvature[i + 1])), 3.0)
          << to_string(sex) << ": a kink " << (profile[i].x() - back.y()) / hu << " head-cm over the opisthocranion";
    ASSERT_GT(glabella_ring, 1u) << to_string(sex);
    ASSERT_LT(glabella_ring + 2, profile.size()) << to_string(sex) << ": no dome ring over the glabella ring";
    EXPECT_LE(std::abs(curvature[glabella_ring + 1] - curvature[glabella_ring - 1]), 3.0) << to_string(sex);
  }
}

// From its base the back of the neck leans forward through C7 into the nape: C7 stands at least
// 6 mm (per 1.70 m) in front of the neck ring's back. With C7 2.5–3 mm in front (before
// 2026-11-29) the back of the neck rose nearly upright to C7 and turned forward there, and from
// behind its lower part showed as a lit collar under the nape's shade.
TEST(MannequinGenerator, NeckLeansForwardThroughC7) {
  for (const auto& [d, sex] : sample_bodies()) {
    const Vertices v = mq::generate(d, sex);
    const auto& lm = mq::topology().landmarks;
    const double y_neck = v(lm.at("neck_front"), 1), z_c7 = v(lm.at("cervicale"), 2);
    double neck_back = 1e9;  // the neck ring's back, on the midline
    for (Eigen::Index i = 0; i < v.rows(); ++i)
      if (v(i, 0) == 0.0 && v(i, 2) < 0 && std::abs(v(i, 1) - y_neck) < 1e-9) neck_back = std::min(neck_back, v(i, 2));
    ASSERT_LT(neck_back, 0.0) << to_string(sex);
    const double cm = 0.01 * d.at("stature") / 1.70;
    EXPECT_GE(z_c7 - neck_back, 0.6 * cm) << to_string(sex) << ", " << d.at("stature") << " m tall";
    EXPECT_LE(z_c7 - neck_back, 2.0 * cm) << to_string(sex) << ", " << d.at("stature") << " m tall";
  }
}

// A man's chest rounds into its sides and is wider at the back (the latissimus) than across the
// front, where ANSUR's chest breadth is taken: on the typical man's chest section the back half
// is at least 3 cm (per 1.70 m) wider than the front half, and on every sample man the front at
// 80 % of its half-breadth lies at least 5 % of the chest's depth behind its most forward point.
// (Women's breasts stand furthest forward about there.)
// With the breadth taken across the whole section (until 2026-11-29) the section had to be as
// square as its bounding box: the back no wider, the front flat to 3 mm at 80 %, a panel.
TEST(MannequinGenerator, ChestRoundsIntoItsSidesAndWidensBehind) {
  int men = 0;
  for (const auto& [d, sex] : sample_bodies()) {
    if (sex != Sex::Male) continue;
    ++men;
    const Vertices v = mq::generate(d, sex);
    const std::vector<Eigen::Vector3d> section = cut(v, mq::topology().faces, v(mq::topology().landmarks.at("chest_front"), 1));
    double front = -1e9, back = 1e9;
    for (const auto& q : section) front = std::max(front, q.z()), back = std::min(back, q.z());
    const double mid = 0.5 * (front + back);
    double half_front = 0, half_back = 0;
    for (const auto& q : section) {
      double& half = q.z() >= mid ? half_front : half_back;
      half = std::max(half, std::abs(q.x()));
    }
    double at_80 = -1e9;  // the front's most forward point at 75–85 % of the front half-breadth
    for (const auto& q : section)
      if (q.z() > mid && std::abs(std::abs(q.x()) / half_front - 0.8) < 0.05) at_80 = std::max(at_80, q.z());
    const std::string body = std::string(to_string(sex)) + ", " + std::to_string(d.at("stature")) + " m";
    ASSERT_GT(at_80, mid) << body;
    EXPECT_GE(front - at_80, 0.05 * (front - back)) << body;
    if (d == mq::typical_dimensions(Sex::Male)) {
      EXPECT_GE(half_back - half_front, 0.015 * d.at("stature") / 1.70) << body;
    }
  }
  EXPECT_EQ(men, 2);
}

// The back's flare widens the man's chest behind its sides gradually, over the whole back half:
// on the chest section every point of the sides (|x| over half the section's half-width) lies
// within 15 mm (per 1.70 m) of the section's convex hull (the sample men and a heavier typical
// man). Until 2026-12-07 the flare rose mostly between 55 and 80 % of the back's depth: a step
// behind the side under the armpit, about 2 cm deep (21.7 mm on the typical man, 24.8 mm on the
// larger one), a vertical ledge down the torso's side in front and three-quarter views.
TEST(MannequinGenerator, ChestWidensBehindItsSidesWithoutAStep) {
  auto heavy = mq::typical_dimensions(Sex::Male);  // the chest and waist 15 % larger every way
  for (auto c : {"chestcircumference", "chestbreadth", "chestdepth", "waistcircumference", "waistbreadth", "waistdepth"})
    heavy[c] *= 1.15;
  std::vector<std::pair<mq::Dimensions, Sex>> men;
  for (const auto& body : sample_bodies())
    if (body.second == Sex::Male) men.push_back(body);
  men.push_back({heavy, Sex::Male});
  for (const auto& body : men) {
    const mq::Dimensions& d = body.first;
    const Vertices v = mq::generate(d, Sex::Male);
    const double y_chest = v(mq::topology().landmarks.at("chest_front"), 1);
    std::vector<Eigen::Vector2d> section;
    for (const auto& q : cut(v, mq::topology().faces, y_chest)) section.emplace_back(q.x(), q.z());
    const std::vector<size_t> hull = convex_hull(section);
    double half_width = 0;
    for (const auto& q : section) half_width = std::max(half_width, std::abs(q.x()));
    double deepest = 0;  // the largest distance from a side point to the hull's boundary
    for (const auto& q : section) {
      if (std::abs(q.x()) < 0.5 * half_width) continue;
      double nearest = 1e9;
      for (size_t i = 0; i < hull.size(); ++i) {
        const Eigen::Vector2d a = section[hull[i]], b = section[hull[(i + 1) % hull.size()]];
        const double t = std::clamp((q - a).dot(b - a) / std::max((b - a).squaredNorm(), 1e-12), 0.0, 1.0);
        nearest = std::min(nearest, (q - a - t * (b - a)).norm());
      }
      deepest = std::max(deepest, nearest);
    }
    EXPECT_LE(deepest, 0.015 * d.at("stature") / 1.70) << d.at("stature") << " m tall, chest " << d.at("chestcircumference");
  }
}

// ANSUR takes the lower thigh's girth just above the knee: its ring stands 4–8 cm (per 1.70 m)
// over the knee's (the kneecap's middle) on every sample body. At 11 cm (until 2026-11-29) the
// thigh narrowed to that girth far too high and heavy bodies stood on thin thighs.
TEST(MannequinGenerator, LowerThighGirthIsTakenJustAboveTheKnee) {
  for (const auto& [d, sex] : sample_bodies()) {
    const Vertices v = mq::generate(d, sex);
    const auto& lm = mq::topology().landmarks;
    const double over = v(lm.at("lower_thigh_left"), 1) - v(lm.at("knee_left"), 1), per = d.at("stature") / 1.70;
    EXPECT_GE(over, 0.04 * per) << to_string(sex) << ", " << d.at("stature") << " m";
    EXPECT_LE(over, 0.08 * per) << to_string(sex) << ", " << d.at("stature") << " m";
  }
}

// The thigh keeps its fullness over the quadriceps' and adductors' bellies and narrows toward
// the knee in its lower third: halfway down from the thigh's girth section to the lower thigh's,
// one leg's section keeps at least 70 % of the difference between their girths. Along the smooth
// curve through the rings (before 2026-11-29) it kept about half, and heavy bodies stood on thin
// legs. Full, not swollen: going down from the thigh's section to the lower thigh's, no section
// (every 5 mm) is more than 1 mm longer round than the one above it.
TEST(MannequinGenerator, ThighKeepsItsFullnessToMidThigh) {
  for (const auto& [d, sex] : sample_bodies()) {
    const Vertices v = mq::generate(d, sex);
    const auto& lm = mq::topology().landmarks;
    auto girth = [&](double y) {
      std::vector<Eigen::Vector2d> flat;
      for (const auto& p : cut(v, mq::topology().faces, y))
        if (p.x() > 0) flat.emplace_back(p.x(), p.z());
      return caliper::convex_hull_perimeter(flat);
    };
    const double y_thigh = v(lm.at("thigh_left"), 1), y_lower = v(lm.at("lower_thigh_left"), 1);
    const double top = girth(y_thigh), lower = girth(y_lower), mid = girth(0.5 * (y_thigh + y_lower));
    const std::string who = std::string(to_string(sex)) + ", " + std::to_string(d.at("stature")) + " m";
    EXPECT_GT(top - lower, 0.05) << who;
    if (top - lower <= 0.05) continue;
    EXPECT_GE((mid - lower) / (top - lower), 0.7) << who << ": girths " << top << ", " << mid << ", " << lower << " m";
    double above = top;
    for (double y = y_thigh - 0.005; y > y_lower; y -= 0.005) {
      const double here = girth(y);
      EXPECT_LE(here, above + 0.001) << who << ": the section " << (y_thigh - y) * 100 << " cm under the thigh's grows";
      above = here;
    }
  }
}

TEST(MannequinGenerator, ButtocksMeetInACleft) {
  for (const auto& [d, sex] : sample_bodies()) {
    const Vertices v = mq::generate(d, sex);
    const auto& lm = mq::topology().landmarks;
    auto at = [&](const char* name) { return Eigen::Vector3d(v.row(lm.at(name)).transpose()); };
    EXPECT_EQ(cleft_failure(v, mq::topology().faces, at, 0.01 * d.at("stature") / 1.70), "") << to_string(sex) << ", " << d.at("stature") << " m tall";
  }
}

// From the side the buttocks stand out over the thighs and round under into the fold. The
// cheek's back-most point on the buttock's section (the hip ring) lies at least 1.5 cm (per
// 1.70 m) behind the thigh's back-most point on the thigh's girth section; and halfway down from
// the hip ring to the gluteal furrow the cheek still lies at least 2 mm behind the straight line
// between those two points. ANSUR's proximal thigh girth makes the thigh nearly as deep as the
// buttocks; centred under them (before 2026-11-28) its back was within 1 cm of theirs and the
// seat ran straight down into the thighs; with the back blended by a smooth step the seat was
// an S-slope, at most 1.1 mm behind the line halfway down on the five bodies (3.3–10 mm now).
TEST(MannequinGenerator, ButtocksStandOutOverTheThighs) {
  for (const auto& [d, sex] : sample_bodies()) {
    const Vertices v = mq::generate(d, sex);
    const auto& lm = mq::topology().landmarks;
    const Faces& f = mq::topology().faces;
    const double cm = 0.01 * d.at("stature") / 1.70;
    auto cheek_at = [&](double y) { return extreme_z(cut(v, f, y), 6.0 * cm, 3.5 * cm, -1); };
    const double y_hip = v(lm.at("buttock_back"), 1), y_thigh = v(lm.at("thigh_left"), 1);
    const double y_mid = 0.5 * (y_hip + v(lm.at("gluteal_furrow"), 1));
    const double cheek = cheek_at(y_hip), cheek_mid = cheek_at(y_mid);
    double thigh = 1e9;
    for (const auto& p : cut(v, f, y_thigh))
      if (p.x() > 0) thigh = std::min(thigh, p.z());
    ASSERT_LT(std::max({cheek, cheek_mid, thigh}), 1e8) << to_string(sex) << ": no section";
    EXPECT_GE(thigh - cheek, 1.5 * cm) << to_string(sex) << ", " << d.at("stature") << " m tall";
    const double line = std::lerp(thigh, cheek, (y_mid - y_thigh) / (y_hip - y_thigh));
    EXPECT_GE(line - cheek_mid, 0.2 * cm) << to_string(sex) << ", " << d.at("stature") << " m tall";
  }
}

// thigh_outline_failures() on the sample bodies (the population test runs it on the development
// data where ../shared is present).
TEST(MannequinGenerator, HipRunsIntoTheThighWithoutAWaist) {
  for (const auto& [d, sex] : sample_bodies()) {
    const Vertices v = mq::generate(d, sex);
    const auto& lm = mq::topology().landmarks;
    auto at = [&](const char* name) { return Eigen::Vector3d(v.row(lm.at(name)).transpose()); };
    const double cm = 0.01 * d.at("stature") / 1.70;
    // (Clang before 16 cannot capture a structured binding in a lambda: the check's text is made here.)
    const std::string who = std::string(to_string(sex)) + ", " + std::to_string(d.at("stature")) + " m";
    thigh_outline_failures(v, mq::topology().faces, at, cm, [&who](bool ok, const std::string& what, double value) {
      EXPECT_TRUE(ok) << who << ": " << what << " (" << value * 1000 << " mm)";
    });
    EXPECT_LE(knee_beyond_hip(v, mq::topology().faces, at, cm), kKneeBeyondHipMost * cm) << who;
  }
}

// knee_beyond_hip() on narrow hips, the bodies it is about: the typical man with ANSUR's hip
// breadth and buttock girth at 90 %. His knee stands at most kKneeBeyondHip cm out past the thigh's
// girth section (6.5 mm with the leg moved in; 16.6 mm before 2026-12-07, and 11.8 mm now at 85 %,
// where his calf's inner side stops the leg).
TEST(MannequinGenerator, KneeStandsUnderANarrowHip) {
  auto d = mq::typical_dimensions(Sex::Male);
  for (auto c : {"hipbreadth", "buttockcircumference"}) d[c] *= 0.9;
  const Vertices v = mq::generate(d, Sex::Male);
  const auto& lm = mq::topology().landmarks;
  auto at = [&](const char* name) { return Eigen::Vector3d(v.row(lm.at(name)).transpose()); };
  const double cm = 0.01 * d.at("stature") / 1.70, knee = knee_beyond_hip(v, mq::topology().faces, at, cm);
  EXPECT_GE(knee, 0);
  EXPECT_LE(knee, kKneeBeyondHip * cm);
}

// The legs lean out (a relaxed stance, the feet about hip-width apart): from the knee down to the
// ankle the middle of the leg's section moves outward by at least 2° of lean (the generator leans
// them 4°, and the lower leg's rings themselves draw in by about 1°). Before 2026-11-28 the legs
// stood parallel and this line leaned inward.
TEST(MannequinGenerator, LegsLeanOutIntoARelaxedStance) {
  for (const auto& [d, sex] : sample_bodies()) {
    const Vertices v = mq::generate(d, sex);
    const auto& lm = mq::topology().landmarks;
    const double y_knee = v(lm.at("knee_left"), 1), y_ankle = v(lm.at("ankle_left"), 1);
    const auto knee = left_leg_span(v, mq::topology().faces, y_knee), ankle = left_leg_span(v, mq::topology().faces, y_ankle);
    ASSERT_TRUE(knee && ankle) << to_string(sex);
    const double out = span_middle(*ankle) - span_middle(*knee);
    const double degrees = std::atan2(out, y_knee - y_ankle) * 180 / std::acos(-1.0);
    EXPECT_GE(degrees, 2.0) << to_string(sex) << ", " << d.at("stature") << " m tall";
    EXPECT_LE(degrees, 8.0) << to_string(sex) << ", " << d.at("stature") << " m tall";
  }
}

// In a relaxed stance the toes turn out a little: each foot's axis, from the heel to the middle
// of the ball (between the breadth's two ends), points outward of straight ahead (+x on the left,
// −x on the right).
TEST(MannequinGenerator, FeetTurnOutInTheStance) {
  for (const auto& [d, sex] : sample_bodies()) {
    const Vertices v = mq::generate(d, sex);
    const auto& lm = mq::topology().landmarks;
    for (const auto& [side, outward] : {std::pair{std::string("_left"), 1.0}, std::pair{std::string("_right"), -1.0}}) {
      const Eigen::RowVector3d heel = v.row(lm.at("heel" + side));
      const Eigen::RowVector3d ball = 0.5 * (v.row(lm.at("foot_medial" + side)) + v.row(lm.at("foot_lateral" + side)));
      const double degrees = std::atan2(outward * (ball.x() - heel.x()), ball.z() - heel.z()) * 180 / std::acos(-1.0);
      EXPECT_GE(degrees, 4.0) << to_string(sex) << side << ", " << d.at("stature") << " m tall";
      EXPECT_LE(degrees, 15.0) << to_string(sex) << side << ", " << d.at("stature") << " m tall";
    }
  }
}

// SMPL and SMPL-H pose data drive the rig by joint name: SMPL's 72 values and SMPL-H's
// 156 land on the joints they name; a model without fingers drops SMPL-H's finger values.
TEST(PoseFromValues, SmplAndSmplhValuesLandOnTheirJoints) {
  const Vertices v = mq::generate(mq::typical_dimensions(Sex::Female), Sex::Female);
  const BodyModel model = model_for(v, Sex::Female);
  std::vector<double> smpl(72, 0.0);
  smpl[16 * 3 + 2] = -0.7;  // SMPL joint 16: left_shoulder
  smpl[21 * 3 + 1] = 0.4;   // 21: right_wrist
  const Pose a = pose_from_axis_angles(model, smpl);
  EXPECT_DOUBLE_EQ(a(joint_named(model, "left_shoulder"), 2), -0.7);
  EXPECT_DOUBLE_EQ(a(joint_named(model, "right_wrist"), 1), 0.4);
  EXPECT_DOUBLE_EQ(a.cwiseAbs().sum(), 1.1);
  std::vector<double> smplh(156, 0.0);
  smplh[18 * 3 + 1] = 0.5;   // left_elbow, as in SMPL
  smplh[22 * 3 + 2] = -1.0;  // SMPL-H joint 22: left_index1 (no hand joints in SMPL-H)
  smplh[51 * 3 + 0] = 0.3;   // 51: right_thumb3
  const Pose h = pose_from_axis_angles(model, smplh);
  EXPECT_DOUBLE_EQ(h(joint_named(model, "left_elbow"), 1), 0.5);
  EXPECT_DOUBLE_EQ(h(joint_named(model, "left_index1"), 2), -1.0);
  EXPECT_DOUBLE_EQ(h(joint_named(model, "right_thumb3"), 0), 0.3);
  EXPECT_DOUBLE_EQ(h(joint_named(model, "left_hand"), 2), 0.0);
  EXPECT_DOUBLE_EQ(h.cwiseAbs().sum(), 1.8);
  // The index finger bends, the middle fingertip stays.
  const Vertices posed = pose_vertices(model, v, h);
  const int middle_tip = mq::topology().landmarks.at("dactylion_left");
  EXPECT_LT((posed.row(middle_tip) - v.row(middle_tip)).norm(), 0.2);  // moved only by the elbow
  // On a model without finger joints the finger values are dropped, the body's kept.
  const BodyModel toy = test::toy_model();
  const Pose t = pose_from_axis_angles(toy, smplh);
  ASSERT_EQ(t.rows(), 24);
  EXPECT_DOUBLE_EQ(t(18, 1), 0.5);
  EXPECT_DOUBLE_EQ(t.cwiseAbs().sum(), 0.5);
}

TEST(PoseFromValues, BadValuesAndDocumentsAreRefusedNamingThePose) {
  const Vertices v = mq::generate(mq::typical_dimensions(Sex::Male), Sex::Male);
  const BodyModel model = model_for(v, Sex::Male);
  Error e = test::catch_error([&] { pose_from_axis_angles(model, std::vector<double>(10, 0.0)); });
  EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
  EXPECT_EQ(e.field(), "pose");
  EXPECT_NE(std::string(e.what()).find("72 (SMPL)"), std::string::npos) << e.what();
  std::vector<double> nan(72, 0.0);
  nan[40] = std::nan("");
  EXPECT_EQ(test::catch_error([&] { pose_from_axis_angles(model, nan); }).kind(), ErrorKind::InvalidArgument);
  // JSON: an array, triples, or an object's "pose" / "poses".
  std::string flat = "[";
  for (int i = 0; i < 72; ++i) flat += (i ? "," : "") + std::string(i == 50 ? "0.25" : "0");
  flat += "]";
  EXPECT_DOUBLE_EQ(pose_from_json(model, flat, "flat")(16, 2), 0.25);
  EXPECT_DOUBLE_EQ(pose_from_json(model, "{\"pose\": " + flat + "}", "object")(16, 2), 0.25);
  std::string triples = "{\"poses\": [";
  for (int i = 0; i < 24; ++i) triples += std::string(i ? "," : "") + (i == 16 ? "[0, 0, 0.25]" : "[0, 0, 0]");
  triples += "]}";
  EXPECT_DOUBLE_EQ(pose_from_json(model, triples, "triples")(16, 2), 0.25);
  for (const std::string bad : {"[1, 2", "{\"pose\": [1, \"a\"]}", "{\"pose\": 3}", "{}", "[[1, 2]]", "\"\xff\""}) {
    e = test::catch_error([&] { pose_from_json(model, bad, "bad.json"); });
    EXPECT_EQ(e.kind(), ErrorKind::Format) << bad;
    EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
  }
  EXPECT_EQ(test::catch_error([&] { pose_from_json(model, std::string(2 << 20, ' '), "big.json"); }).kind(), ErrorKind::Format);
  EXPECT_EQ(test::catch_error([&] { load_pose(model, "/nonexistent/pose.json"); }).kind(), ErrorKind::Io);
}

// The stride pose (docs/images/mannequin-posed.png) bends the joints the way its name says, and
// only those: the left foot swings forward, the right one back, the hands come down and forward.
TEST(MannequinGenerator, StridePoseSwingsTheLimbsWhereItSays) {
  const Vertices v = mq::generate(mq::typical_dimensions(Sex::Female), Sex::Female);
  const BodyModel model = model_for(v, Sex::Female);
  const Vertices posed = pose_vertices(model, v, stride_pose(model));
  ASSERT_TRUE(posed.allFinite());
  const auto& lm = mq::topology().landmarks;
  auto moved = [&](const std::string& name) -> Eigen::Vector3d {
    const int i = lm.at(name);
    return (posed.row(i) - v.row(i)).transpose();
  };
  EXPECT_GT(moved("heel_left").z(), 0.05);    // forward
  EXPECT_LT(moved("heel_right").z(), -0.05);  // back
  EXPECT_GT(moved("heel_left").y(), 0.03);    // the bent knee lifts the foot
  for (const char* hand : {"dactylion_left", "dactylion_right"}) {
    EXPECT_LT(moved(hand).y(), -0.3) << hand;  // arms lowered
    EXPECT_GT(moved(hand).z(), 0.1) << hand;   // forearms forward
  }
  EXPECT_LT(moved("vertex").norm(), 1e-9);  // head and trunk stay
  EXPECT_LT(moved("omphalion").norm(), 1e-9);
  // Nothing flies off: no vertex travels farther than a whole arm swinging down.
  EXPECT_LT((posed - v).rowwise().norm().maxCoeff(), 0.9);
}

TEST(MannequinGenerator, BadInputsThrowNamingTheField) {
  auto d = mq::typical_dimensions(Sex::Female);
  auto expect_field = [&](mq::Dimensions dims, const std::string& field) {
    try {
      mq::generate(dims, Sex::Female);
      ADD_FAILURE() << "no throw for " << field;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
      EXPECT_EQ(e.field(), field);
    }
  };
  auto bad = d;
  bad["waistcircumference"] = std::nan("");
  expect_field(bad, "waistcircumference");
  bad = d;
  bad["span"] = -1.0;
  expect_field(bad, "span");
  bad = d;
  bad["hipbreadth"] = 354.0;  // millimetres typed for metres
  expect_field(bad, "hipbreadth");
  bad = d;
  bad.erase("footlength");
  expect_field(bad, "footlength");
  bad = d;
  bad["stature"] = 17.0;
  expect_field(bad, "stature");
}

TEST(MannequinGenerator, CompleteDimensionsScalesByStature) {
  const auto typical = mq::typical_dimensions(Sex::Male);
  const auto d = mq::complete_dimensions({{"stature", 2 * typical.at("stature")}, {"span", 3.0}}, Sex::Male);
  EXPECT_DOUBLE_EQ(d.at("span"), 3.0);
  EXPECT_DOUBLE_EQ(d.at("footlength"), 2 * typical.at("footlength"));
  EXPECT_EQ(d.size(), typical.size());
}

// Fidelity over ANSUR development subjects: every target within 3 mm / 1 %. Every 15th subject
// (all with CALIPER_EVERY_SUBJECT=1),
// plus every subject whose own levels force the construction off its usual plan (generator.cpp):
// gluteal furrow or trochanterion at or below the crotch, axilla below the bust point, a navel
// close above the seat, a head circumference beyond what its breadth and length allow at p = 4.
TEST(MannequinGenerator, ReproducesAnsurSubjects) {
  const std::string dir = std::string(CALIPER_SHARED_DIR) + "/data/ansur2/";
  if (!std::filesystem::exists(dir + "ANSUR_II_FEMALE_dev.csv"))
    GTEST_SKIP() << "ANSUR II data not found in " << dir << " (needs ../shared next to the repo)";
  const auto targets = mq::fidelity_targets();
  const auto regions = vertex_regions(mq::topology().skin_weights, rig_joint_names());
  // CALIPER_EVERY_SUBJECT=1 checks all 4,552 (about 4 minutes), as docs/mannequin.md reports.
  const bool every_subject = std::getenv("CALIPER_EVERY_SUBJECT") != nullptr;
  // In the sanitizer build a body costs about 1.7 s instead of ~55 ms (un-inlined Eigen), so the
  // default run there is a thin sample of both kinds: every 600th subject and every 40th unusual
  // one, about 20 bodies (35 s), so memory and UB errors on the unusual construction paths still
  // show. CALIPER_SANITIZE_FULL=1 restores the Release sample
  // (scripts/sanitize.sh then runs this test outside ctest's timeout; docs/reliability.md,
  // "Sanitizers").
#ifdef CALIPER_SANITIZED
  const bool thin = !every_subject && std::getenv("CALIPER_SANITIZE_FULL") == nullptr;
#else
  const bool thin = false;
#endif
  const size_t stride = thin ? 600 : 15, unusual_stride = thin ? 40 : 1;
  size_t unusual_seen = 0;
  int bodies = 0, unusual_bodies = 0, grown_chests = 0, knees_out = 0;
  std::map<std::string, int> misses;
  for (const char* file : {"ANSUR_II_FEMALE_dev.csv", "ANSUR_II_MALE_dev.csv"}) {
    const auto subjects = read_ansur_csv(dir + file);
    for (size_t i = 0; i < subjects.size(); ++i) {
      const auto& s = subjects[i];
      const auto& x = s.values;
      const bool unusual = x.at("buttockheight") < x.at("crotchheight") + 0.01 ||
                           x.at("trochanterionheight") < x.at("crotchheight") + 0.01 ||
                           x.at("axillaheight") < x.at("chestheight") + 0.012 ||
                           x.at("waistheightomphalion") < std::max(x.at("buttockheight"), x.at("trochanterionheight")) + 0.07 ||
                           x.at("headcircumference") > 1.75 * (x.at("headbreadth") + x.at("headlength"));
      const bool take_unusual = unusual && unusual_seen++ % unusual_stride == 0;
      if (i % stride != 0 && !take_unusual && !every_subject) continue;
      if (unusual) ++unusual_bodies;
      mq::Dimensions dims;
      for (const auto& c : mq::input_columns()) dims[c] = s.values.at(c);
      const Vertices v = mq::generate(dims, s.sex);
      const BodyModel model = model_for(v, s.sex);
      const auto m = measure_all(model, v);
      ++bodies;
      // No part of the surface passes through another (thighs into each other, arms into the
      // torso, the jaw into the neck).
      const auto crossings = self_intersections(v, mq::topology().faces, 1);
      EXPECT_TRUE(crossings.empty()) << "subject " << s.id << ": faces " << crossings[0].first << " and "
                                     << crossings[0].second << " cross";
      // Creases (crease.h) in the regions that should be smooth stay at or below the lofted
      // body's levels over the whole development set (`caliper model creases --ansur`,
      // docs/mannequin.md "Creases"): a change that folds the surface more fails here.
      for (const auto& r : crease_report(v, mq::topology().faces, regions)) {
        if (is_feature_region(r.region)) continue;
        const double p99_bound = r.region == BodyRegion::Legs ? 52 : r.region == BodyRegion::Arms ? 38 : 50;
        EXPECT_LE(r.p99_degrees, p99_bound) << "subject " << s.id << ", " << to_string(r.region);
        EXPECT_LE(r.max_degrees, 130) << "subject " << s.id << ", " << to_string(r.region) << " edge " << r.worst.a << "-" << r.worst.b;
      }
      for (const auto& miss : relief_failures(model, v, dims)) ADD_FAILURE() << "subject " << s.id << ": " << miss;
      {
        auto at = [&](const char* name) { return Eigen::Vector3d(v.row(mq::topology().landmarks.at(name)).transpose()); };
        const double cm = 0.01 * dims.at("stature") / 1.70, knee = knee_beyond_hip(v, mq::topology().faces, at, cm);
        EXPECT_GE(knee, 0) << "subject " << s.id << ": no thigh section";
        EXPECT_LE(knee, kKneeBeyondHipMost * cm) << "subject " << s.id << ": knee out past the thigh's girth section";
        if (knee > kKneeBeyondHip * cm) ++knees_out;
      }
      // A chest whose circumference even a flared back does not reach grows in breadth and depth
      // by one factor (generator.cpp header): there both are traded, not missed. The excuse is
      // bounded: by at most 10 % (the development data's largest is under 7 %), on a man, and on
      // at most a tenth of the bodies (28 of 3,062 men, 0 of 1,490 women of the development data;
      // 193 men before 2026-12-07).
      const double depth_factor = m.at("chest_depth") / dims.at("chestdepth");
      const double breadth_factor = m.at("chest_breadth") / dims.at("chestbreadth");
      const bool chest_grew = s.sex == Sex::Male && depth_factor > 1.001 && depth_factor < 1.10 &&
                              std::abs(breadth_factor - depth_factor) < 0.01;
      grown_chests += chest_grew;
      for (const auto& t : targets) {
        const double want = dims.at(t.ansur_column), got = m.at(t.measurement);
        bool ok = t.circumference ? std::abs(got - want) <= 0.01 * want : std::abs(got - want) <= 0.003;
        if (!ok && chest_grew && (t.measurement == "chest_breadth" || t.measurement == "chest_depth")) ok = true;
        if (!ok) ++misses[t.measurement];
      }
    }
  }
  ASSERT_GT(bodies, thin ? 15 : 250);
  EXPECT_LE(grown_chests, bodies / 10);
  EXPECT_LE(knees_out * 100, std::max(bodies, 100)) << knees_out << " of " << bodies << " knees more than " << kKneeBeyondHip
                                                   << " cm out past the thigh's girth section (knee_beyond_hip())";
  EXPECT_GT(unusual_bodies, thin ? 8 : 300);  // the development subset has ~450 of them
  for (const auto& [name, n] : misses) ADD_FAILURE() << name << " missed on " << n << " of " << bodies << " bodies";
}
