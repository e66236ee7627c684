// The built-in body generator: ANSUR II dimensions → a closed fixed-topology mesh in a
// T-pose. Construction: lofted rings. The torso, neck and head are one stack of horizontal
// rings (y = const) closed by a pole at the vertex; each leg is a stack of horizontal rings
// ending in a foot whose rings morph into the footprint and whose sole is zipped flat on y = 0,
// with five toe tubes growing like the thumb from holes in the forefoot's front;
// each arm is a stack of rings in planes x = const, starting from a rectangular hole in the
// torso's side (the armpit), ending in a mitten hand with a thumb tube growing from a hole in
// the hand's radial side. The crotch joins the torso's bottom ring to the two legs through a
// front-to-back bridge of vertices shared by both legs' first rings.
//
// After the rings, the shoulder and the groin are faired (fair()) and anatomy is drawn on the surface as
// horizontal displacements that keep every target (sculpt(), "Relief" below; docs/mannequin.md);
// last, the legs lean out into a relaxed stance and the toes turn out (splay_legs() and
// turn_feet_out(), which keep every section's shape).
//
// Fidelity by construction (brief; paper §3.2 for how Caliper measures): every imposed
// breadth/depth/circumference sits on a planar ring, so the plane section through its landmark is
// exactly that ring polygon; ring scales and the superellipse exponent ("boxiness") are solved so
// the polygon's extents and convex-hull perimeter hit the targets. Heights are ring levels.
//
// Documented compromises (see fidelity_targets()):
//  * Arms: ANSUR's arm segments are measured hanging; in a T-pose biacromial/2 + acromion→radiale
//    + radiale→stylion + hand length overshoots span/2 by ~9–10 cm. Span, biacromial breadth and
//    hand length are exact; the upper arm and forearm are scaled by one common factor so the
//    fingertips land at ±span/2 (the paper's real→virtual map, §3.3, handles arm length).
//  * Some levels are points on one side of the body, not whole rings, so ANSUR's orderings
//    between them can differ from the rings' order: the iliac crest (side) may lie above or below
//    the navel (front), the axilla (side) up to 1.7 cm below the bust point (front), and the
//    trochanterion (side) and gluteal furrow (back) below the crotch. Rings are tilted at the side
//    or back to reach them; where horizontal sections are measured across tilted rings, those rings
//    re-sample the same surface so the sections are unchanged.
//  * Where a circumference is larger than its breadth and depth allow with a plausible profile
//    (superellipse exponent ≤ 5 for the waist, 6 for the hip, 10 for the head), the
//    circumference is kept and the ring grows in depth; the head and hip rings' exponents keep
//    every subject's head length and buttock depth.
//  * The chest is ANSUR's hard case: its circumference is large for its breadth × depth
//    (C / ellipse perimeter 1.24 on average for men; above the bounding rectangle's perimeter for
//    435 of 4,082 men). Chest breadth is taken across the front half of the section
//    (MeasurementKind::FrontBreadth: a caliper's blades on the chest's sides, in front of the
//    arms), so the back may be wider. The front rounds into the sides (exponent ≤ kChestP), and
//    the back squares (≤ kChestBackP) and then flares behind the sides (the latissimus, up to
//    kChestFlareMax) until the tape is long enough; only where even that falls short do breadth
//    and depth grow by one common factor (docs/mannequin.md, "The chest"). The section is solved
//    as sculpt() leaves it, with the chest's relief cut into it. With breadth the section's full
//    width (until 2026-11-29) every man's chest was as square as its box (exponent up to 14), a
//    flat panel; with the depth alone growing (until 2026-11-24) it was a barrel.
//  * Thigh circumference is imposed on a leg ring 3 cm (scaled by stature) below the crotch, or
//    lower under a seat that drops below it: a horizontal section at ANSUR's level, the gluteal
//    furrow, would cut the torso.
//  * Biceps and forearm girths use 0.9 × ANSUR's flexed values as relaxed girths (not targets).
#include "caliper/mannequin/generator.h"
#include "caliper/measure/geometry.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <set>

#include "caliper/errors.h"
#include "curve.h"

namespace caliper::mannequin {

using detail::MonotoneCurve;
using detail::QuinticEnd;
using detail::quintic_hermite;
using detail::smoothstep;
using Vec3 = Eigen::Vector3d;

namespace {

constexpr double kPi = 3.14159265358979323846;

// ---- Fixed topology constants ------------------------------------------------------------
constexpr int kTorsoN = 64;    // points per torso ring; j = 0 front centre, j = 16 body's left
constexpr int kLegN = 40;      // points per leg ring (33 from the torso half + 7 crotch bridge)
constexpr int kBridge = 7;     // interior crotch bridge vertices
constexpr int kArmN = 32;      // points per arm ring (= armpit hole boundary)
constexpr int kHoleJ0 = 12, kHoleJ1 = 20;  // armpit hole columns on the left side
constexpr int kHoleRows = 8;                // ring intervals spanned by the armpit hole
constexpr int kThumbQ0 = 27, kThumbQ1 = 31; // thumb hole columns on the hand (q = 28 is +Z), a little under its edge
constexpr int kThumbRows = 3;
// Fairing of the shoulder (fair()): torso columns beside the armpit hole, arm rings after it.
// kFairArmTaper more arm rings take a shrinking share of each step (3/4, 1/2, 1/4).
constexpr int kFairColumns = 6, kFairArmRings = 3, kFairArmTaper = 3, kFairIterations = 30;
// Smoothing the shoulder's skin weights (smooth_shoulder_weights()): full within the inner radius
// of the shoulder joint, fading to none at the outer (metres on a 1.70 m body).
constexpr double kShoulderSmoothInner = 0.04, kShoulderSmoothOuter = 0.12;
constexpr int kShoulderSmoothRounds = 15;
// Fairing of the groin: the torso's bottom rings and the legs' first rings (above the thigh ring).
constexpr int kFairGroinTorsoRings = 2, kFairGroinLegRings = 2;
constexpr double kCrotchOpen = 0.008;  // m on a 1.70 m body: see build()
constexpr int kThumbN = 2 * (kThumbQ1 - kThumbQ0) + 2 * kThumbRows;

// Torso key levels and ring intervals between consecutive keys.
enum TorsoKey {
  kBottom, kLow, kHip, kWaist, kIlio, kUnderBust, kChest, kArmpit, kAxilla, kHoleTop, kShoulder1, kShoulder2,
  kNeck, kCervicale, kChin, kMouth, kNose, kGlabella, kTorsoKeyCount
};
// kArmpit: the axilla landmark's ring, just under the armpit hole whose bottom is kAxilla.
// The face has rings about 5 mm apart from the chin to the mouth, 2.5 mm from the mouth to the
// nose and 1.6 mm from the nose to the glabella, so the relief (sculpt()) can draw lips, nose and
// the eyes' lids; six rings between the cervicale and the chin let the
// fairing round the neck and the jaw's border under the chin (make_fairing()).
constexpr std::array<int, kTorsoKeyCount - 1> kTorsoIntervals = {2, 3, 8, 1, 6, 3, 3, 1, kHoleRows, 2, 2, 2, 1, 6, 8, 16, 30};
// The chest's section (plan_body(); generator.cpp's header): its front at most as square as a
// superellipse of exponent kChestP, so it rounds into the sides instead of standing as a flat
// panel; the back may square up to kChestBackP and then flare behind the sides by up to
// kChestFlareMax of the half-breadth before the ring has to grow.
constexpr double kChestP = 3.5, kChestBackP = 6.5, kChestFlareMax = 0.55;
// The jaw's lower border rises from the chin to the angle of the jaw: the chin ring's sides are
// lifted by this share of the face's height (glabella to chin), the mouth ring's by 40 % of it, so
// from the front the jaw is a U meeting the neck below its angles, not a level shelf.
constexpr double kJawLift = 0.15;
// The chin ring's front: a share of the head's half-length in front of the head's centre, and the
// chin's bump on it (m per unit of the head's scale).
constexpr double kChinFront = 0.84, kChinBump = 0.006;
// The neck ring (it carries the neck's girth) lies this far under the chin (m on a 1.70 m body),
// unless 6 mm under C7 is lower; and the cervicale ring's front leans toward the chin's (see
// plan_body()), so the neck's front leans forward up to the floor of the mouth. Below the neck
// ring the trapezius spreads toward the shoulders, so the closer it lies to the chin, the shorter
// the column of neck under the jaw. (At 2.6 cm, until 2026-12-07, the neck was a column about
// 4 cm long from the jaw down, seen from the front and from behind, on shoulders that flared out
// only at its foot; at 1.2 cm there was hardly any neck under the jaw. At 3 cm the throat's bend
// fell on the torso's side of the neck ring; docs/mannequin.md.)
constexpr double kNeckBelowChin = 0.018;
// The share of the way from its own front to the chin's that the cervicale ring's front takes
// (times its share of the height from the neck ring to the chin ring). At 0.5 (until 2026-12-07),
// with the neck ring nearer the chin, the throat leaned up from it so steeply that the neck ring
// folded at the midline, 8° more on the typical man than with the ring 2.6 cm under the chin.
constexpr double kJawFloorFront = 0.35;
// The trapezius' two rings between the shoulders' top and the neck ring (plan_body()). Each stands
// a share of the way in from the shoulders' half-breadth to the neck's: the lower one
// kTrapeziusLowIn; the upper one kTrapeziusHighIn, or further in where its slope from the neck
// ring (half-breadth gained per height) would pass kTrapeziusSlope, but never further in than
// kTrapeziusHighInMost. Their fronts narrow toward the midline (TorsoRing::front_taper).
constexpr double kTrapeziusLowIn = 0.28;
constexpr double kTrapeziusHighIn = 0.55, kTrapeziusHighInMost = 0.75;
constexpr double kTrapeziusSlope = 1.9;
constexpr double kTrapeziusLowTaper = 0.10, kTrapeziusHighTaper = 0.25;
// The two rings' heights, as shares of the height from the acromion to the neck ring; and their
// fronts' and backs' places, as shares of the way from the shoulders' top ring's to the neck's.
constexpr double kTrapeziusLowAt = 0.3, kTrapeziusHighAt = 0.6;
constexpr double kTrapeziusLowFront = 0.6, kTrapeziusLowBack = 0.35;
constexpr double kTrapeziusHighFront = 0.88, kTrapeziusHighBack = 0.8;
// The legs' outward lean in the rest pose (splay_legs()): the feet stand about hip-width apart.
constexpr double kLegSplay = 4.0 * kPi / 180;
constexpr double kLegSplayRamp = 0.10;  // m below the crotch (per 1.70 m) over which the lean sets in
// The feet's turn outward in the rest pose (turn_feet_out()), each about the leg's vertical axis
// at the malleolus: people stand with their toes a little apart, not parallel.
constexpr double kToeOut = 8.0 * kPi / 180;
// The buttocks' cleft (TorsoRing::cleft): its depth on a 24 cm buttock depth (scaled with it), and
// the distance from the midline at which that depth falls to 1/e (m).
constexpr double kCleftDepth = 0.035, kCleftWidth = 0.024;
// The seat in profile: the thigh's centre stands this share of the buttock depth in front of the
// hip section's middle, and the back from the hip ring down to the torso's bottom ring (and the
// cheeks' bumps down to the gluteal furrow's ring) follow 1 − (1 − u)^kSeatRoundUnder, u = 1 at
// the hip ring: full, then rounding under.
constexpr double kThighForward = 0.08;
constexpr double kSeatRoundUnder = 3.0;
// The gluteal fold's line (add_back_relief()): lowest kFoldDrop cm (per 1.70 m) under ANSUR's
// furrow height at kFoldLowest of the way out to the thigh's outer side, rising as the square by
// kFoldRiseMedial cm to the midline and kFoldRiseLateral cm to the thigh's outer side.
constexpr double kFoldLowest = 0.45, kFoldDrop = 1.0, kFoldRiseMedial = 1.2, kFoldRiseLateral = 2.0;
static_assert(kFoldLowest > 0 && kFoldLowest < 1);
constexpr int kDomeRings = 12;  // rings above the glabella ring before the pole
constexpr double kOcciputMaxBend = 20;  // plan_body(): the bound on the nape-to-occiput quintic's ends
constexpr double kFaceDensity = 3.5;  // extra column density across the face (respace_torso_columns)
constexpr double kEarDensity = 2.0;   // and across the ears
// In head centimetres (sculpt()): the nose's wings' middles from the midline and their radius
// across; how the mouth's line falls toward its corners, kMouthDroop·(X − kMouthLevelHalf)² beyond
// the middle stretch kMouthLevelHalf either side of the midline, which stays level.
constexpr double kAlaX = 1.4, kAlaRadius = 0.9;
constexpr double kMouthDroop = 0.35, kMouthLevelHalf = 1.0;
// The eye's opening (eye_opening()): its middle, half-width, and the lids' heights over and
// under its middle line; the margins' width; how far the eye lies behind the lids' margins.
constexpr double kEyeX = 3.1, kEyeY = -2.75, kEyeHalfWidth = 1.45, kEyeUp = 0.5, kEyeDown = 0.35;
constexpr double kEyeMargin = 0.22, kEyeRecess = 0.22;
// How much deeper the eye lies toward the opening's corners than at its middle (a share of
// kEyeRecess at the corners, falling as the square toward the middle), and the upper lid's rim:
// its height and the band it stands on (face_height(), upper_lid_rim()).
constexpr double kEyeCornerRecess = 1.0, kLidRim = 0.08, kLidRimWidth = 0.3;
// The ear, in head centimetres from the glabella (Y up, scaled by the face's height; Z forward
// of the head's centre): its centre and half-height and half-width.
constexpr double kEarY = -4.3, kEarZ = -1.1, kEarRY = 2.8, kEarRZ = 1.7;

// Leg stations (below the theta ring r0) and intervals.
enum LegKey { kLegTop, kThigh, kLowerThigh, kKnee, kCalf, kAnkle, kMalleolus, kLegKeyCount };
constexpr std::array<int, kLegKeyCount - 1> kLegIntervals = {1, 8, 3, 5, 7, 2};
// The lower thigh's girth ring over the knee ring (m per 1.70 m; plan_body()). The knee's relief
// ends under it (leg_relief()): sculpt() does not move a girth ring.
constexpr double kLowerThighOverKnee = 0.06;
// The late fall of the thigh's girth toward the knee (thigh_fullness()): the power n of
// early_falloff(). Halfway from the thigh's girth ring to the lower thigh's the thigh keeps 26 % of
// the difference between them more than the smooth curve does (77–81 % of it on the sample bodies,
// the curve about half). At 4 the thigh just above the lower thigh's ring grew too: one heavy
// woman's kneecap stood 2.8 mm out of the leg's line, under the relief check's 3 mm.
constexpr double kThighFullness = 3.5;
// The least gap between a leg ring's inner side and the midline (m), before the legs splay,
// below the thigh's girth ring (which keeps 4 mm; plan_body()).
constexpr double kLegMidlineGap = 0.003;
constexpr std::array<double, 7> kFootLevels = {0.78, 0.58, 0.42, 0.29, 0.18, 0.09, 0.035};  // × malleolus height
constexpr int kFootBreadthRing = 6;  // index into foot rings (+ the sole ring after them)
// Index into foot rings: the heel's fullest back, which carries the heel landmark (the foot length
// is taken from it). It is also the toes' holes' top ring, whose front the toes' wall rewrites
// (plan_body()); that keeps each ring's back, so the heel stays where heel_profile() puts it.
constexpr int kHeelRing = 3;
// Toes, big toe (medial) to little toe: tubes grown like the thumb from holes in the forefoot's
// front. Each hole spans foot rings kToeRing .. kToeRing + 2 (one interior ring, whose vertex at
// the toe's column is left out) and the columns beside its own; neighbouring holes share those.
constexpr int kToeCount = 5;
constexpr int kToeRing = 3;  // index into foot rings: the holes' upper edge
constexpr std::array<int, kToeCount> kToeColumns = {2, 4, 6, 8, 10};
// The forefoot's front, columns kToeSpanFirst (medial) on through kToeSpanColumns columns, is
// re-spaced along the footprint's outline (foot_angles()) so each toe's hole gets a toe's share of
// it: left alone, the columns crowd the front's middle and leave the big toe under 1 cm.
constexpr int kToeSpanFirst = 38, kToeSpanColumns = 16;
// Where those columns sit along the outline: 0 → 1 from the span's medial end to the front
// (column kLegFront, which stays at the front so the sole's zip runs toe to heel on both sides),
// 1 → 2 from there to the lateral end, as fractions of each part's length. The holes' edges (odd
// columns 1–11) split the front as a big toe and four smaller ones share it; the second toe meets
// the third at the front.
constexpr std::array<double, kToeSpanColumns> kToeSpacing = {0, 0.07, 0.14, 0.21, 0.44, 0.68, 0.84, 1,
                                                               1.12, 1.25, 1.37, 1.5, 1.62, 1.74, 1.87, 2};
// The forefoot's front wall, where the toes leave it, at this fraction of the foot length from the
// heel (the webs between the toes lie about there).
constexpr double kToeWall = 0.85;
// Rings along a toe at these fractions of its length from the hole.
constexpr std::array<double, 9> kToeAt = {0.12, 0.25, 0.38, 0.5, 0.62, 0.73, 0.83, 0.91, 0.97};

// Arm stations (x = const rings) after the hole ring r0.
// kKnuckle: the knuckles (MCP joints, hand breadth); kWeb: the webs between the fingers, where
// the hand's last ring splits into the four fingers.
enum ArmKey { kRoot, kDeltoid, kAcromion, kDeltoidLow, kBiceps, kElbow, kForearm, kWrist, kPalm, kThumbTop, kKnuckle, kWeb, kArmKeyCount };
constexpr std::array<int, kArmKeyCount - 1> kArmIntervals = {1, 1, 3, 3, 4, 3, 6, 2, kThumbRows, 3, 2};

// Fingers, index to little finger (+Z to −Z on the T-posed left hand, palm down). Each grows from
// an arc of the web ring's columns q (one contiguous loop around the finger, listed in ring order);
// every column belongs to one finger, and the gaps between neighbouring arcs are the webs.
enum Finger { kIndex, kMiddle, kRing, kPinky, kFingerCount };
const std::array<std::vector<int>, kFingerCount> kFingerColumns = {{
    {24, 25, 26, 27, 28, 29, 30, 31, 0},  // top, the front side, bottom
    {20, 21, 22, 23, 1, 2, 3, 4},
    {16, 17, 18, 19, 5, 6, 7, 8},
    {9, 10, 11, 12, 13, 14, 15},          // bottom, the back side, top
}};
// Rings along a finger at these fractions of its length from the knuckle (MCP joint) to the tip;
// kPipRing and kDipRing are the middle and end joints (phalanges ≈ 0.48 : 0.30 : 0.22 of the
// length), where rings sit close so the finger bends cleanly.
// The webs: between index and middle, middle and ring, ring and little finger (top, top, bottom,
// bottom columns).
constexpr std::array<std::array<int, 4>, kFingerCount - 1> kWebQuads = {{{24, 23, 1, 0}, {20, 19, 5, 4}, {16, 15, 9, 8}}};
constexpr std::array<double, 15> kFingerM = {0.22, 0.29, 0.36, 0.42, 0.48, 0.54, 0.61, 0.68, 0.74, 0.78, 0.83, 0.89, 0.94, 0.975, 0.995};
constexpr int kPipRing = 4, kDipRing = 9;  // indices into kFingerM
// Thumb rings at fractions of its length from the palm; joints 2 and 3 at kThumbU[4] and [8].
constexpr std::array<double, 14> kThumbU = {0.15, 0.23, 0.31, 0.37, 0.42, 0.48, 0.56, 0.64, 0.72, 0.8, 0.87, 0.93, 0.97, 0.993};
constexpr int kThumbMcpRing = 4, kThumbIpRing = 8;

int torso_key_ring(int key) {
  int k = 0;
  for (int i = 0; i < key; ++i) k += kTorsoIntervals[static_cast<size_t>(i)];
  return k;
}
int leg_key_ring(int key) {  // ring index counted from r0 = theta ring; leg top = 1
  int k = 1;
  for (int i = 0; i < key; ++i) k += kLegIntervals[static_cast<size_t>(i)];
  return k;
}
int arm_key_ring(int key) {  // r0 = hole ring, root = 1
  int k = 1;
  for (int i = 0; i < key; ++i) k += kArmIntervals[static_cast<size_t>(i)];
  return k;
}
constexpr int torso_ring_count() {
  int k = 1;
  for (int v : kTorsoIntervals) k += v;
  return k + kDomeRings;
}
constexpr int leg_ring_count() {  // r0..malleolus + foot rings + sole ring
  int k = 2;
  for (int v : kLegIntervals) k += v;
  return k + static_cast<int>(kFootLevels.size()) + 1;
}
constexpr int arm_ring_count() {  // r0..web ring
  int k = 2;
  for (int v : kArmIntervals) k += v;
  return k;
}
// The face's fine rings: each has a vertex halfway between every two of its columns as well
// (Builder::fine) over the face and the ears, so they are drawn on a grid about 2 mm across
// instead of 4 mm (an eye had five columns). They run from kFineAboveChin rings over the chin
// ring up to the ring under the glabella ring, which carries the head's measures and stays as
// it is; under the first, the jaw's fairing keeps its one-rings (static_assert at
// make_fairing()). Round the head from the front's middle to column kFineColumns and from its
// mirror image back to the middle: the ears reach column 22 on the development bodies; the back
// of the head, which has no features, keeps its columns (each fine vertex costs the estimator's
// every step, docs/performance.md).
constexpr int kFineAboveChin = 4, kFineColumns = 24;
int fine_first() { return torso_key_ring(kChin) + kFineAboveChin; }
int fine_last() { return torso_key_ring(kGlabella) - 1; }

// Leg ring angles φ (0 = front, 90° = lateral, 180° = back, 270° = medial). The first 33 come
// from the torso's half ring, the last 7 from the crotch bridge; 0/90/180/270° are exact points.
double leg_angle(int k) {
  constexpr double d1 = 90.0 / 11.0, d2 = (360.0 - 32 * d1) / 8.0;
  const double deg = k <= 32 ? -5 * d1 + k * d1 : -5 * d1 + 32 * d1 + (k - 32) * d2;
  return deg * kPi / 180.0;
}
constexpr int kLegFront = 5, kLegLateral = 16, kLegBack = 27, kLegMedial = 36;
constexpr int kLegBridgeFirst = 33;  // leg columns from here on are the crotch bridge's

double arm_angle(int q) { return (-45.0 + q * 360.0 / kArmN) * kPi / 180.0; }
constexpr int kArmBottom = 4, kArmBack = 12, kArmTop = 20, kArmFront = 28;

double spow(double v, double e) { return v < 0 ? -std::pow(-v, e) : std::pow(v, e); }
double sq(double v) { return v * v; }
// Where a body lies between the sexes' shapes: 1 for women, 0 for men, 0.5 for the neutral body.
double femininity(Sex sex) { return sex == Sex::Female ? 1.0 : sex == Sex::Male ? 0.0 : 0.5; }
// 1 at the centre, 0 beyond the ellipse of radii (rx, ry), C² in between.
double blob(double dx, double dy, double rx, double ry) {
  const double r2 = sq(dx / rx) + sq(dy / ry);
  return r2 >= 1 ? 0.0 : (1 - r2) * (1 - r2) * (1 - r2);
}

// 0 → 1 over [a0, a1], then 1 → 0 over [b0, b1] (each ramp at least 1 mm long).
double window(double v, double a0, double a1, double b0, double b1) {
  return smoothstep(a0, std::max(a1, a0 + 1e-3), v) * (1 - smoothstep(b0, std::max(b1, b0 + 1e-3), v));
}

// ---- Ring shapes -------------------------------------------------------------------------
struct TorsoRing {
  double y = 0, a = 0.1, df = 0.1, db = 0.1, cz = 0, p = 2.5;
  double bust = 0, bust_t = 0.75, bust_w = 0.32;  // bust bumps: amplitude (m), angle, width (rad)
  double bust_w_out = 0;                           // the bumps' width on their outer side (0: bust_w)
  double glute = 0;                                // buttock bumps (m)
  double cleft = 0;                                // the buttocks' cleft at the back's midline: depth (m)
  double nose = 0, chin = 0;                       // face bumps (m)
  double front_taper = 0;  // the front half narrows by this share toward the midline (x × (1 − taper·cos²))
  // The back half: how much its exponent exceeds p (squarer), and how much wider it grows behind
  // the sides (x × (1 + flare·w), w rising smoothly from 0 at kFlareFrom of the back's depth to 1
  // at kFlareRise): the latissimus and the shoulder blades, which make a man's chest wider at the
  // back than across the front. Spread over most of the back's depth the widening slants the side
  // out; until 2026-12-07 it rose mostly between 55 and 80 % of the depth and stood behind the
  // side as a step. Starting the rise at the side itself (tried) folded the chest ring against the
  // capped axilla ring just above it, up to 127° on men whose armpit is at their chest's height.
  double back_squareness = 0, flare = 0;
};
constexpr double kFlareFrom = 0.25, kFlareRise = 0.95;

// The buttock cheeks' bump's shape around the ring: 1 at kCheekAngle from the back's midline,
// falling to 1/e kCheekWidth (rad) either side. at = |t|, t in (−π, π].
constexpr double kCheekAngle = 0.62, kCheekWidth = 0.42;
double glute_bump(double at) { return std::exp(-sq((at - (kPi - kCheekAngle)) / kCheekWidth)); }

Eigen::Vector2d torso_xz(const TorsoRing& r, double t) {
  const double s = std::sin(t), c = std::cos(t), e = 2.0 / (c < 0 ? r.p + r.back_squareness : r.p);
  // The flare's weight follows the depth behind the side (|z − cz| / db = |c|^e).
  const double flare_weight = c < 0 ? smoothstep(kFlareFrom, kFlareRise, std::pow(-c, e)) : 0;
  double x = r.a * spow(s, e) * (c > 0 ? 1 - r.front_taper * c * c : 1 + r.flare * flare_weight);
  double z = r.cz + (c >= 0 ? r.df : r.db) * spow(c, e);
  double tt = std::remainder(t, 2 * kPi);  // (−π, π]
  const double at = std::abs(tt);
  if (r.bust != 0) {
    const double w = at > r.bust_t && r.bust_w_out > 0 ? r.bust_w_out : r.bust_w;
    const double g = std::exp(-std::pow((at - r.bust_t) / w, 2));
    z += r.bust * g;
    x += 0.25 * r.bust * g * (tt >= 0 ? 1 : -1);
  }
  if (r.glute != 0) z -= r.glute * glute_bump(at);
  // The cleft between the buttocks: a groove along the back's midline, as wide in metres on every
  // ring (kCleftWidth), whatever the ring's breadth. Back half only: the front's midline is x = 0 too.
  if (r.cleft != 0 && c < 0) z += r.cleft * std::exp(-sq(x / kCleftWidth));
  if (r.nose != 0) z += r.nose * std::exp(-std::pow(at / 0.12, 2));
  if (r.chin != 0) z += r.chin * std::exp(-std::pow(at / 0.45, 2));
  return {x, z};
}

std::vector<Eigen::Vector2d> torso_polygon(const TorsoRing& r) {
  std::vector<Eigen::Vector2d> pts(kTorsoN);
  for (int j = 0; j < kTorsoN; ++j) pts[static_cast<size_t>(j)] = torso_xz(r, 2 * kPi * j / kTorsoN);
  return pts;
}

// Sets df and db so the ring's front extent is front and its back extent is back (relative to cz).
void fit_depths(TorsoRing& r, double front, double back) {
  // z is affine in df (front points) and db (back points): evaluate the polygon twice, then
  // bisect on the cheap affine form.
  r.df = r.db = 0;
  const auto p0 = torso_polygon(r);
  r.df = r.db = 1;
  const auto p1 = torso_polygon(r);
  for (int side = 0; side < 2; ++side) {
    const double target = side == 0 ? front : back;
    auto extent = [&](double v) {
      double ext = -1e9;
      for (size_t j = 0; j < p0.size(); ++j) {
        const double z = p0[j].y() + v * (p1[j].y() - p0[j].y()) - r.cz;
        ext = std::max(ext, side == 0 ? z : -z);
      }
      return ext;
    };
    double lo = 0.2 * target, hi = 1.5 * target;
    for (int it = 0; it < 50; ++it) {
      const double mid = 0.5 * (lo + hi);
      (extent(mid) < target ? lo : hi) = mid;
    }
    (side == 0 ? r.df : r.db) = 0.5 * (lo + hi);
  }
}

// ---- The chest's relief ------------------------------------------------------------------
// sculpt() draws the chest's features on the lofted surface; on the chest's own section it may
// only move vertices inward, which shortens the tape and the depth there. The chest's ring is
// therefore solved with its relief applied (fit_torso_ring), so the section sculpt() leaves has
// ANSUR's breadth, depth and girth.
struct ChestFrame {
  bool female = false;
  double fem = 0;  // 1 for women, 0 for men, 0.5 for the neutral body
  double cm = 0;   // one centimetre on a 1.70 m body
  double y_w = 0, y_us = 0, y_ch = 0, y_ax = 0, y_acr = 0;  // key rings: waist … shoulders' top
  double a_ch = 0;                                          // the chest's half-breadth
};
ChestFrame chest_frame(Sex sex, double sc, double y_w, double y_us, double y_ch, double y_ax, double y_acr) {
  ChestFrame F;
  F.female = sex == Sex::Female;
  F.fem = femininity(sex);
  F.cm = 0.01 * sc;
  F.y_w = y_w; F.y_us = y_us; F.y_ch = y_ch; F.y_ax = y_ax; F.y_acr = y_acr;
  return F;
}

// The chest's features (metres, outward) at (x from the midline, height y) of the left half;
// `front` fades from 1 on the torso's front to 0 at its sides: the groove between the pectorals
// or breasts, men's pectorals' lower border, women's fold under each breast and the breasts'
// upper slope.
void add_chest_relief(const ChestFrame& F, double x, double y, double front, double& h) {
  const double cm = F.cm;
  // Groove between the pectorals / breasts, running on as the linea alba to the navel.
  const double g = F.female ? 0.75 * cm : 0.90 * cm;
  const double along = window(y, F.y_w + 2 * cm, F.y_us, F.y_acr - 8 * cm, F.y_acr - 2.5 * cm);
  const double upper = smoothstep(F.y_us - 3 * cm, F.y_us + 4 * cm, y);
  h -= front * along * std::lerp(0.3 * g, g, upper) * blob(x, 0, std::lerp(2.5, F.female ? 4.5 : 5.0, upper) * cm, 1);
  // Men: the pectorals' lower border. The muscle stands over the ribs below it: a step, level
  // across the chest 3.5 cm under the chest ring, rising 5.5 cm into the armpit's front fold from
  // a third of the half-breadth out; under it the ribs lie lower, by up to 1 cm about 3 cm under
  // the border, easing back out within 10 cm of it. The step is spread over 4.5 cm: the rings
  // there lie 2.4–3.4 cm apart, and over 2.3 cm it folded the chest ring 55°. As a groove along
  // a parabola from the sternum (until 2026-11-29) the border read as a diagonal crease from
  // each armpit down to the sternum, worst in the A-pose; deeper and narrower (1.1 cm, rising
  // over 2.6 cm), as a line across the chest.
  if (!F.female) {
    const double yb = F.y_ch - 3.5 * cm + 5.5 * cm * smoothstep(0.35, 0.95, x / F.a_ch);
    const double dy = y - yb;
    const double under = (1 - smoothstep(-3.5 * cm, 1.0 * cm, dy)) * (dy < 0 ? blob(dy, 0, 10.0 * cm, 1) : 1.0);
    h -= front * (1 - F.fem) * 1.4 * cm * under * window(x, 1.0 * cm, 3.5 * cm, 0.9 * F.a_ch, 1.15 * F.a_ch);
  }
  // Women: the fold under each breast.
  if (F.fem > 0) {
    const double xb = 0.62 * F.a_ch;
    const double yb = F.y_ch - 7.0 * cm + 2.5 * cm * sq((x - xb) / (0.45 * F.a_ch));
    const double dy = y - yb;
    const double prof = dy > 0 ? blob(dy, 0, 2.0 * cm, 1) : blob(dy, 0, 3.5 * cm, 1);
    h -= front * F.fem * 0.6 * cm * prof * blob(x - xb, 0, 0.6 * F.a_ch, 1);
  }
  // Women: the breasts' upper slope eases into the upper chest (the lofted profile bends
  // there, a line across the chest).
  if (F.fem > 0)
    h += front * F.fem * 0.45 * cm * blob(x - 0.55 * F.a_ch, y - (F.y_ax - 0.5 * cm), 0.7 * F.a_ch, 3.5 * cm);
}

// How much of the torso's relief a point at angle t round its ring carries as the front's (1
// on the front, 0 from the sides back; torso_relief()).
double front_share(double t) { return smoothstep(0.25, 0.65, std::cos(t)); }

// The ring's polygon as sculpt() leaves it on the chest's section: each point moved along the
// ring's outward normal by the inward part of the chest's relief there (none without a frame).
std::vector<Eigen::Vector2d> section_polygon(const TorsoRing& r, const ChestFrame* relief) {
  std::vector<Eigen::Vector2d> pts = torso_polygon(r);
  if (!relief) return pts;
  ChestFrame f = *relief;
  f.a_ch = r.a;
  std::vector<Eigen::Vector2d> out(pts.size());
  const size_t n = pts.size();
  for (size_t j = 0; j < n; ++j) {
    const Eigen::Vector2d tangent = pts[(j + 1) % n] - pts[(j + n - 1) % n];
    const Eigen::Vector2d outward = Eigen::Vector2d(-tangent.y(), tangent.x()).normalized();
    double h = 0;
    add_chest_relief(f, std::abs(pts[j].x()), r.y, front_share(2 * kPi * static_cast<double>(j) / kTorsoN), h);
    out[j] = pts[j] + std::min(h, 0.0) * outward;
  }
  return out;
}

// fit_depths() for the section sculpt() leaves: the relief's loss at the front and back is
// measured and asked for on top (it hardly depends on the depths, so a few rounds settle it).
void fit_section_depths(TorsoRing& r, double front, double back, const ChestFrame* relief) {
  double extra_front = 0, extra_back = 0;
  for (int round = 0;; ++round) {
    fit_depths(r, front + extra_front, back + extra_back);
    if (!relief || round == 3) return;
    double f = -1e9, b = -1e9;
    for (const auto& q : section_polygon(r, relief)) { f = std::max(f, q.y() - r.cz); b = std::max(b, r.cz - q.y()); }
    extra_front += front - f;
    extra_back += back - b;
  }
}

// The skull above the glabella ring: a quarter-superellipse of exponent kDomeE in profile, at
// superellipse angle th (0: the glabella ring, π/2: the vertex). With 2, a quarter-ellipse, the
// forehead slopes back from the brow and the crown comes to a point (an egg); a real forehead
// rises nearly upright for a few centimetres and the crown is broad. A superellipse of exponent
// over 2 starts without curvature, though, while the head under its widest ring is curved: the
// back of the head showed a band along the glabella ring. So the sides and the back (not the
// forehead, which stays upright) give up ½ kDomeBase u² (1 − u)² of their scale at height u over
// the glabella ring (a share of the dome's height): their scale's second derivative in u starts
// at −kDomeBase, as an ellipse's does, instead of 0, and the crown is as it was (at most 3.4 %
// narrower, about halfway up; with (1 − u)⁴ the curvature was gone 1.3 cm up, which only moved
// the band).
constexpr double kDomeE = 2.6, kDomeBase = 1.0;
// The superellipse angle at height u over the glabella ring (a share of the dome's height).
double dome_angle(double u) { return std::asin(std::pow(u, kDomeE / 2)); }
TorsoRing dome_ring(const TorsoRing& glabella, double vertex_y, double hs, double th) {
  TorsoRing r = glabella;
  const double u = std::pow(std::sin(th), 2 / kDomeE);
  r.y = glabella.y + (vertex_y - glabella.y) * u;
  const double c = std::pow(std::cos(th), 2 / kDomeE);
  const double rounded = c - 0.5 * kDomeBase * sq(u * (1 - u));
  r.a *= rounded; r.df *= c;
  r.db *= rounded * (1 - 0.03 * (1 - c));  // the back flattens gradually: no step at the glabella ring
  r.cz = glabella.cz - 0.012 * hs * (1 - c);
  return r;
}

// Lowers the ring's flare (bisection) until the ring reaches no further out than half_width;
// flare = 0 where even that does not.
void cap_flare(TorsoRing& r, double half_width) {
  auto reach = [&](double flare) {
    TorsoRing trial = r;
    trial.flare = flare;
    double x = 0;
    for (const auto& q : torso_polygon(trial)) x = std::max(x, std::abs(q.x()));
    return x;
  };
  if (reach(r.flare) <= half_width) return;
  double lo = 0, hi = r.flare;
  if (reach(lo) > half_width) {
    r.flare = 0;
    return;
  }
  for (int it = 0; it < 30; ++it) {
    const double mid = 0.5 * (lo + hi);
    (reach(mid) <= half_width ? lo : hi) = mid;
  }
  r.flare = lo;
}

// How a ring too small for its circumference grows (the circumference is always kept).
enum class Growth { Depth, BreadthAndDepth };

// The profiles a ring may take to reach its circumference, in the order they are tried: the
// exponent p from p_min up to p_max; then (the chest) the back half squarer, up to p_back_max,
// and wider behind the sides (over most of the back's depth), by up to flare_max; then it grows
// (`growth`).
struct RingFit {
  double p_min = 1.7, p_max = 4.5;
  Growth growth = Growth::Depth;
  double p_back_max = 0, flare_max = 0;
  const ChestFrame* relief = nullptr;  // solve for the section sculpt() leaves (the chest)
};

// Solves the ring so its section has breadth 2a (across its front half: the back may flare),
// depth front + back and hull perimeter = circumference.
void fit_torso_ring(TorsoRing& r, double breadth, double depth, double front_fraction, double circumference,
                    const RingFit& fit) {
  r.a = breadth / 2;
  r.p = fit.p_min;
  r.back_squareness = r.flare = 0;
  auto perimeter = [&](double d) {
    fit_section_depths(r, front_fraction * d, (1 - front_fraction) * d, fit.relief);
    return convex_hull_perimeter(section_polygon(r, fit.relief));
  };
  // Bisects `param` over [lo, hi] for the circumference; false (param = hi) if hi falls short.
  auto solve = [&](double& param, double lo, double hi) {
    param = hi;
    if (perimeter(depth) < circumference) return false;
    for (int it = 0; it < 40; ++it) {
      param = 0.5 * (lo + hi);
      (perimeter(depth) < circumference ? lo : hi) = param;
    }
    param = 0.5 * (lo + hi);
    perimeter(depth);
    return true;
  };
  if (perimeter(depth) > circumference) return;  // rounder than p_min allows: keep p_min
  if (solve(r.p, fit.p_min, fit.p_max)) return;
  if (fit.p_back_max > fit.p_max && solve(r.back_squareness, 0, fit.p_back_max - fit.p_max)) return;
  if (fit.flare_max > 0 && solve(r.flare, 0, fit.flare_max)) return;
  // Infeasible for the profile family: grow the depth, or breadth and depth by one factor.
  const bool both = fit.growth == Growth::BreadthAndDepth;
  double lo = 1, hi = 2;
  for (int it = 0; it < 40; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (both) r.a = mid * breadth / 2;
    (perimeter(mid * depth) < circumference ? lo : hi) = mid;
  }
  if (both) r.a = hi * breadth / 2;
  perimeter(hi * depth);
}

struct LegRing {
  double y = 0, xc = 0.1, zc = 0, al = 0.06, am = 0.06, bf = 0.06, bb = 0.06, p = 2.2, calf = 0;
  // Feet only: the front half's exponent (0: p), and how far the front's lateral corner falls
  // back (the toes' line slants from the big toe to the little one).
  double p_front = 0, toe_slant = 0;
  // Feet only: the back half narrows toward the heel by this share (x × (1 − heel·c²)), and the
  // medial side further where the arch is (behind the ball: the arch's share at c² = ½).
  double heel = 0, arch = 0;
  // Feet only: how far (0–1) the front columns are re-spaced for the toes (foot_angles()).
  double toe_spacing = 0;
};
// The calf's bulge behind the shin, as a share of LegRing::calf: the gastrocnemius' two heads
// either side of the back (phi = π), the inner one the fuller, so the calf's fullest back lies
// toward its inner side (one bump at the back centred it).
double calf_heads(double phi) {
  auto head = [phi](double centre) { return std::exp(-sq(std::remainder(phi - centre, 2 * kPi) / 0.62)); };
  return 1.15 * head(-(kPi - 0.55)) + 0.85 * head(kPi - 0.55);
}
Eigen::Vector2d leg_xz(const LegRing& r, double phi) {  // left leg: lateral = +X
  const double s = std::sin(phi), c = std::cos(phi);
  const double e = 2.0 / (c > 0 && r.p_front > 0 ? r.p_front : r.p);
  // The back half's share of its half-breadth, narrowed toward the heel and at the arch.
  const double width = c < 0 ? 1 - r.heel * c * c - (s < 0 ? 4 * r.arch * c * c * (1 - c * c) : 0.0) : 1.0;
  double x = r.xc + (s >= 0 ? r.al : r.am) * spow(s, e) * width;
  double z = r.zc + (c >= 0 ? r.bf : r.bb) * spow(c, e);
  if (c > 0 && s > 0) z -= r.toe_slant * c * c * s;
  if (r.calf != 0) z -= r.calf * calf_heads(phi);
  return {x, z};
}
// The angles of a leg ring's columns: leg_angle(), except on a foot ring whose front is re-spaced
// for the toes (kToeSpacing): there the columns between the span's ends move along the outline to
// their share of its length, by the ring's toe_spacing.
std::array<double, kLegN> foot_angles(const LegRing& r) {
  std::array<double, kLegN> phi{};
  for (int k = 0; k < kLegN; ++k) phi[static_cast<size_t>(k)] = std::remainder(leg_angle(k), 2 * kPi);
  if (r.toe_spacing <= 0) return phi;
  auto column = [](int m) { return static_cast<size_t>((kToeSpanFirst + m) % kLegN); };
  const std::array<double, 3> ends = {phi[column(0)], 0.0, phi[column(kToeSpanColumns - 1)]};
  for (int part = 0; part < 2; ++part) {
    const double a = ends[static_cast<size_t>(part)], b = ends[static_cast<size_t>(part + 1)];
    constexpr int kSamples = 256;
    std::vector<double> length(kSamples + 1, 0.0);
    for (int i = 1; i <= kSamples; ++i)
      length[static_cast<size_t>(i)] = length[static_cast<size_t>(i - 1)] +
                                       (leg_xz(r, a + (b - a) * i / kSamples) - leg_xz(r, a + (b - a) * (i - 1) / kSamples)).norm();
    size_t i = 1;
    for (int m = 1; m + 1 < kToeSpanColumns; ++m) {
      const double share = kToeSpacing[static_cast<size_t>(m)] - part;
      if (share <= 0 || share >= 1) continue;
      const double want = share * length.back();
      while (i < kSamples && length[i] < want) ++i;
      const double f = (want - length[i - 1]) / std::max(1e-15, length[i] - length[i - 1]);
      const double spaced = a + (b - a) * (static_cast<double>(i - 1) + f) / kSamples;
      phi[column(m)] = std::lerp(phi[column(m)], spaced, r.toe_spacing);
    }
  }
  return phi;
}

// Between two key rings a section's size may fall off early or late rather than along the smooth
// curve through the rings. early_falloff(u, n) = g(u) − (1 − 3u² + 2u³), g(u) = (1 − u)^n (1 + n u):
// negative where g lies under the cubic, i.e. where a section that falls early lies under the
// curve, as a share of the difference between the key rings. Both are 1 at u = 0, 0 at u = 1 and
// flat at either end, so the curve's own slopes carry through the key rings.
double early_falloff(double u, double n) {
  return std::pow(1 - u, n) * (1 + n * u) - (1 - 3 * u * u + 2 * u * u * u);
}

// Below the calf ring the calf's muscle bellies end about halfway down to the ankle and the leg
// goes on narrow, over the tendons: the section's size falls from the calf's toward the ankle's
// earlier than the smooth curve through the rings, which drew a cone. The ring r (interpolated by
// that curve) takes on, of the difference between calf and ankle, the share early_falloff(u, 2.5).
// u: 0 at the calf, 1 at the ankle.
void shin_taper(LegRing& r, const LegRing& calf, const LegRing& ankle, double u) {
  const double early = early_falloff(u, 2.5);
  auto taper = [early](double& v, double at_calf, double at_ankle) { v += early * (at_calf - at_ankle); };
  taper(r.al, calf.al, ankle.al); taper(r.am, calf.am, ankle.am);
  taper(r.bf, calf.bf, ankle.bf); taper(r.bb, calf.bb, ankle.bb); taper(r.calf, calf.calf, ankle.calf);
}

double leg_girth(const LegRing& r) {
  std::vector<Eigen::Vector2d> pts(kLegN);
  for (int k = 0; k < kLegN; ++k) pts[static_cast<size_t>(k)] = leg_xz(r, leg_angle(k));
  return convex_hull_perimeter(pts);
}

// Uniform scale about the centre so the (convex) ring's hull perimeter is c.
void fit_leg_circumference(LegRing& r, double c) {
  const double s = c / leg_girth(r);
  r.al *= s; r.am *= s; r.bf *= s; r.bb *= s; r.calf *= s;
}

// Scale of the depth alone (front, back, calf) so the ring's hull perimeter is c; the girth grows
// with the depth, so halving a bracket round the scale converges. (thigh_fullness() only narrows
// the ring first, so the scale is at least 1; the bracket's top doubles until it holds it.)
void fit_leg_depth(LegRing& r, double c) {
  const LegRing r0 = r;
  auto girth_at = [&](double s) {
    r.bf = r0.bf * s; r.bb = r0.bb * s; r.calf = r0.calf * s;
    return leg_girth(r);
  };
  double lo = 0.25, hi = 4.0;
  for (int i = 0; i < 20 && girth_at(hi) < c; ++i) hi *= 2;
  for (int i = 0; i < 50; ++i) {
    const double s = 0.5 * (lo + hi);
    (girth_at(s) < c ? lo : hi) = s;
  }
}

// How far splay_legs() moves the legs' sections at height y outward: nothing at the crotch, a lean
// whose slope grows over the first kLegSplayRamp (per 1.70 m, sc) below it, then the whole lean
// down to the lateral malleolus (foot_y), under which the foot moves as one piece.
double splay_offset(double y, double crotch_y, double foot_y, double sc) {
  const double lean = std::tan(kLegSplay), ramp = kLegSplayRamp * sc;
  const double below = crotch_y - std::max(y, foot_y);
  if (below <= 0) return 0.0;
  return below < ramp ? lean * below * below / (2 * ramp) : lean * (below - 0.5 * ramp);
}

// The thigh keeps its fullness down over the bellies of the quadriceps and the adductors and
// narrows toward the knee in its lower third. Along the smooth curve from the thigh's girth ring
// to the lower thigh's it thinned at an even rate: the typical man's thigh halfway down had 52 cm
// of girth (the 178 cm, 82 kg man's at 40 % of stature 52, MakeHuman's body's at the same
// measurements 58), and heavy bodies stood on thin legs under full hips. The ring r gains, of the two rings' difference in girth, the share
// −early_falloff(1 − u, kThighFullness): mirrored, a section that falls late lies over the curve.
// It keeps its shape, stays kLegMidlineGap clear of the midline, as the rings below are, and no
// further out than the thigh's ring once the legs splay: `lean` is how much further out
// splay_legs() moves it than that ring. Its outer side stood at the thigh ring's and the lean
// (about 7 mm there) carried it out beyond, by 6 mm on the typical woman at mid-thigh (until
// 2026-12-07): from the front and behind, the side's outline narrowed under the hip into a waist
// at the crotch and widened again, the buttocks standing out as balls over the thighs. What the
// ring cannot take in breadth it takes in depth. u: 0 at the thigh ring, 1 at the lower thigh's.
void thigh_fullness(LegRing& r, const LegRing& thigh, const LegRing& lower, double u, double lean) {
  const double want = leg_girth(r) - early_falloff(1 - u, kThighFullness) * (leg_girth(thigh) - leg_girth(lower));
  fit_leg_circumference(r, want);
  r.al = std::min(r.al, thigh.xc + thigh.al - lean - r.xc);
  r.am = std::min(r.am, r.xc - kLegMidlineGap);
  fit_leg_depth(r, want);
}

// The legs lean out from the crotch (splay_legs()), and on narrow hips that carried the knee out
// past the hip's line: from the front the thigh ran straight down from the hip and the knee stood
// out beside it as a knob (until 2026-12-07, by up to 2.1 cm on men of the development data).
// Where the lower thigh's girth ring or the knee's would stand, once the legs lean, further out
// than the thigh's girth ring, the leg from the lower thigh's ring down moves in toward the
// midline by as much, as far as every one of its key rings stays kLegMidlineGap clear of the
// midline (the calf's inner head is the first to reach it): the knee comes under the hip and the
// foot stands that much closer.
// `splay(y)`: how far splay_legs() will move the section at height y out.
void keep_knee_under_hip(std::array<LegRing, kLegKeyCount>& L, const std::function<double(double)>& splay) {
  auto out = [&](const LegRing& r) { return r.xc + r.al + splay(r.y); };
  double shift = std::max(out(L[kLowerThigh]), out(L[kKnee])) - out(L[kThigh]);
  for (int k = kLowerThigh; k < kLegKeyCount; ++k) {
    const LegRing& r = L[static_cast<size_t>(k)];
    shift = std::min(shift, r.xc - r.am - kLegMidlineGap);
  }
  if (shift <= 0) return;
  for (int k = kLowerThigh; k < kLegKeyCount; ++k) L[static_cast<size_t>(k)].xc -= shift;
}

struct ArmRing {
  double x = 0, yc = 0, zc = 0, ry = 0.04, rz = 0.04, p = 2.2;
  // 0: columns at equal angles ψ (arm_angle); 1: at equal arc length within each quarter. The
  // flat hand needs the latter, or its columns bunch at the hand's edges and leave the back of
  // the hand, where the fingers start, with a few wide columns.
  double flat = 0;
};
Vec3 arm_point(const ArmRing& r, double psi) {  // left arm
  const double e = 2.0 / r.p;
  return {r.x, r.yc - r.ry * spow(std::cos(psi), e), r.zc - r.rz * spow(std::sin(psi), e)};
}
// The angles of ring r's columns (see ArmRing::flat). Quarters run between the bottom, back, top
// and front columns, which keep their angles, and are mirror images of the first.
std::array<double, kArmN> arm_column_angles(const ArmRing& r) {
  std::array<double, kArmN> angles{};
  for (int q = 0; q < kArmN; ++q) angles[static_cast<size_t>(q)] = arm_angle(q);
  if (r.flat <= 0) return angles;
  constexpr int kQuarter = kArmN / 4, kSamples = 256;
  std::array<double, kSamples + 1> length{};  // arc length from ψ = 0 (bottom) to ψ = 90° (back)
  Eigen::Vector2d prev(-r.ry, 0);
  for (int i = 1; i <= kSamples; ++i) {
    const Vec3 p = arm_point(r, 0.5 * kPi * i / kSamples);
    const Eigen::Vector2d cur(p.y() - r.yc, p.z() - r.zc);
    length[static_cast<size_t>(i)] = length[static_cast<size_t>(i - 1)] + (cur - prev).norm();
    prev = cur;
  }
  auto equal_arc = [&](int k) {  // ψ in [0, 90°] at k/kQuarter of the quarter's length
    const double target = length.back() * k / kQuarter;
    const auto it = std::lower_bound(length.begin(), length.end(), target);
    const auto i = std::max<std::ptrdiff_t>(1, it - length.begin());
    const double t = (target - length[static_cast<size_t>(i - 1)]) /
                     std::max(1e-15, length[static_cast<size_t>(i)] - length[static_cast<size_t>(i - 1)]);
    return 0.5 * kPi * (static_cast<double>(i - 1) + t) / kSamples;
  };
  for (int q = 0; q < kArmN; ++q) {
    const int qb = ((q - kArmBottom) % kArmN + kArmN) % kArmN;  // columns from the bottom
    const int quarter = qb / kQuarter, k = qb % kQuarter;
    double psi = 0;
    switch (quarter) {
      case 0: psi = equal_arc(k); break;
      case 1: psi = kPi - equal_arc(kQuarter - k); break;
      case 2: psi = kPi + equal_arc(k); break;
      default: psi = 2 * kPi - equal_arc(kQuarter - k); break;
    }
    double base = angles[static_cast<size_t>(q)];  // the same angle, unwrapped to [0, 2π) from the bottom
    while (base < 0) base += 2 * kPi;
    if (qb == 0) base = 0;
    angles[static_cast<size_t>(q)] = (1 - r.flat) * base + r.flat * psi;
  }
  return angles;
}
void fit_arm_circumference(ArmRing& r, double c) {
  std::vector<Eigen::Vector2d> pts(kArmN);
  for (int q = 0; q < kArmN; ++q) {
    const Vec3 v = arm_point(r, arm_angle(q));
    pts[static_cast<size_t>(q)] = {v.y(), v.z()};
  }
  const double s = c / convex_hull_perimeter(pts);
  r.ry *= s;
  r.rz *= s;
}

// ---- Dimensions --------------------------------------------------------------------------
const std::vector<std::string> kColumns = {
    "stature", "cervicaleheight", "acromialheight", "axillaheight", "chestheight", "waistheightomphalion",
    "iliocristaleheight", "trochanterionheight", "buttockheight", "crotchheight", "kneeheightmidpatella",
    "lateralmalleolusheight", "chestbreadth", "chestdepth", "chestcircumference", "waistbreadth", "waistdepth",
    "waistcircumference", "hipbreadth", "buttockdepth", "buttockcircumference", "biacromialbreadth",
    "neckcircumference", "thighcircumference", "lowerthighcircumference", "calfcircumference",
    "anklecircumference", "acromionradialelength", "radialestylionlength", "span", "wristcircumference",
    "bicepscircumferenceflexed", "forearmcircumferenceflexed", "handlength", "handbreadth", "footlength",
    "footbreadthhorizontal", "headbreadth", "headlength", "headcircumference"};

// ANSUR II development-subset means, mm, in kColumns order (computed from the CSVs).
constexpr std::array<double, 40> kFemaleMeans = {
    1628.5, 1395.7, 1335.1, 1239.1, 1171.6, 980.0, 995.3, 845.1, 833.3, 782.0, 448.9, 62.8, 269.2, 247.2,
    946.4, 300.0, 212.9, 861.0, 354.0, 233.0, 1021.6, 365.4, 330.0, 616.1, 401.1, 373.5, 215.8, 311.2,
    241.0, 1659.6, 154.8, 305.5, 264.3, 181.0, 78.2, 246.3, 92.7, 147.7, 189.7, 560.6};
constexpr std::array<double, 40> kMaleMeans = {
    1756.1, 1517.2, 1440.7, 1329.1, 1291.1, 1056.3, 1061.4, 900.5, 887.5, 845.7, 488.3, 72.9, 289.4, 253.7,
    1058.6, 326.6, 237.7, 940.9, 345.8, 246.0, 1019.6, 415.6, 397.7, 625.4, 409.6, 392.6, 229.4, 335.0,
    267.7, 1813.2, 176.0, 358.2, 310.1, 193.2, 88.3, 271.2, 101.9, 154.3, 199.5, 574.4};

struct Dims {  // the inputs, metres, by field
  double S, cerv, acr, axl, chh, wh, ilio, troch, bh, crh, knee, mall, cb, cd, cc, wb, wd, wc, hb, bd, bc, biac,
      neckc, thighc, lthighc, calfc, anklec, ua, fa, span, wristc, bicepsf, forearmf, handl, handb, footl, footb,
      headb, headl, headc;
};
Dims to_dims(const Dimensions& d) {
  std::array<double, 40> v{};
  for (size_t i = 0; i < kColumns.size(); ++i) v[i] = d.at(kColumns[i]);
  Dims r;
  double* out = &r.S;
  for (size_t i = 0; i < v.size(); ++i) out[i] = v[i];
  return r;
}

void validate(const Dimensions& dims, Sex sex) {
  const Dimensions typical = typical_dimensions(sex);
  auto it = dims.find("stature");
  if (it == dims.end()) throw Error(ErrorKind::InvalidArgument, "mannequin: missing dimension 'stature'", "stature");
  const double stature = it->second;
  if (!std::isfinite(stature) || stature < 0.8 || stature > 2.5)
    throw Error(ErrorKind::InvalidArgument, "mannequin: stature must be in [0.8, 2.5] m", "stature");
  const double scale = stature / typical.at("stature");
  for (const auto& c : kColumns) {
    auto f = dims.find(c);
    if (f == dims.end()) throw Error(ErrorKind::InvalidArgument, "mannequin: missing dimension '" + c + "'", c);
    const double v = f->second, expect = typical.at(c) * scale;
    if (!std::isfinite(v) || v <= 0)
      throw Error(ErrorKind::InvalidArgument, "mannequin: dimension '" + c + "' must be a positive number (metres)", c);
    // Generous bounds relative to a proportionally scaled typical body: catches unit mistakes.
    if (v < 0.45 * expect || v > 2.2 * expect)
      throw Error(ErrorKind::InvalidArgument,
                  "mannequin: dimension '" + c + "' = " + std::to_string(v) + " m is implausible for stature " +
                      std::to_string(stature) + " m (accepted " + std::to_string(0.45 * expect) + "–" +
                      std::to_string(2.2 * expect) + " m)", c);
  }
  const double foot = dims.at("crotchheight");
  if (foot >= dims.at("chestheight") || dims.at("chestheight") >= dims.at("acromialheight") ||
      dims.at("acromialheight") >= stature || dims.at("kneeheightmidpatella") >= foot ||
      dims.at("lateralmalleolusheight") >= dims.at("kneeheightmidpatella"))
    throw Error(ErrorKind::InvalidArgument,
                "mannequin: heights must increase malleolus < knee < crotch < chest < acromion < stature",
                "crotchheight");
}

// ---- The body builder --------------------------------------------------------------------
enum class Part { Torso, Bridge, Leg, Arm, Thumb, Finger, Pole };
// UV islands (uv_layout): the faces of each, in the order build() emits them.
enum Island { kIslandTorso, kIslandLeg, kIslandSole = kIslandLeg + 2, kIslandArm = kIslandSole + 2,
              kIslandThumb = kIslandArm + 2, kIslandFinger = kIslandThumb + 2,
              kIslandWeb = kIslandFinger + 2 * kFingerCount, kIslandToe = kIslandWeb + 2,
              kIslandCount = kIslandToe + 2 * kToeCount };

struct Builder {
  // Geometry output.
  std::vector<Vec3> v;
  // Topology output (filled only when want_topology).
  bool want_topology = false;
  std::vector<std::array<int, 3>> faces;
  std::map<std::string, int> landmarks;
  // Per-vertex info for the rig.
  std::vector<Part> part;
  std::vector<int> side;  // +1 left, −1 right, 0 centre

  // Indices of ring structures (left side; the right side is the mirror).
  std::vector<std::vector<int>> torso;  // [ring][j], −1 inside the armpit holes
  // The face's fine rings (fine_first() .. fine_last()): [ring − fine_first()][j], the vertex
  // halfway between columns j and j + 1 (mod kTorsoN), or −1 where the ring has none there.
  std::vector<std::vector<int>> fine;
  int torso_at(int k, int j) const { return torso[static_cast<size_t>(k)][static_cast<size_t>(j)]; }
  int fine_at(int k, int j) const {  // −1 off the fine rings
    return k < fine_first() || k > fine_last() ? -1 : fine[static_cast<size_t>(k - fine_first())][static_cast<size_t>(j)];
  }
  int head_pole = -1;
  std::vector<int> bridge;
  std::array<std::vector<std::vector<int>>, 2> leg, arm, thumb;  // [side][ring][k]; a digit's ring 0 is its base loop
  std::array<std::array<std::vector<std::vector<int>>, kFingerCount>, 2> finger;  // [side][finger][ring][k]
  std::array<int, 2> thumb_pole{};
  std::array<std::array<int, kFingerCount>, 2> finger_pole{};  // fingertips; the middle one's is the dactylion
  std::array<std::array<std::vector<std::vector<int>>, kToeCount>, 2> toe;  // [side][toe][ring][k]
  std::array<std::array<int, kToeCount>, 2> toe_pole{};  // toe tips; the big toe's is the foot length's end
  std::vector<std::pair<size_t, int>> island_starts;  // (first face, Island), in face order

  void island(int id) {
    if (want_topology) island_starts.push_back({faces.size(), id});
  }

  int add(const Vec3& p, Part pt, int sd) {
    v.push_back(p);
    part.push_back(pt);
    side.push_back(sd);
    return static_cast<int>(v.size()) - 1;
  }
  void tri(int a, int b, int c, bool flip) {
    if (!want_topology) return;
    if (flip) faces.push_back({a, c, b});
    else faces.push_back({a, b, c});
  }
  // Quad strip between two rings of equal size; standard orientation: ring order × tube direction
  // points outward (flip reverses). Quads i where skip(i) holds are left open (holes).
  void strip(const std::vector<int>& A, const std::vector<int>& B, bool flip,
             const std::function<bool(size_t)>& skip = nullptr) {
    const size_t n = A.size();
    for (size_t i = 0; i < n; ++i) {
      if (skip && skip(i)) continue;
      const size_t i1 = (i + 1) % n;
      tri(A[i], A[i1], B[i1], flip);
      tri(A[i], B[i1], B[i], flip);
    }
  }
  // A quad a, b, c, d counter-clockwise seen from outside, as two triangles cut along a–c, or
  // along b–d (other_diagonal).
  void quad(int a, int b, int c, int d, bool other_diagonal) {
    if (other_diagonal) { tri(a, b, d, false); tri(b, c, d, false); }
    else { tri(a, b, c, false); tri(a, c, d, false); }
  }
  void fan(const std::vector<int>& A, int pole, bool flip) {
    for (size_t i = 0; i < A.size(); ++i) tri(A[i], A[(i + 1) % A.size()], pole, flip);
  }
};

Vec3 mirror(const Vec3& p) { return {-p.x(), p.y(), p.z()}; }

// fn(k, j, id, mirror_id) for each halfway vertex of the fine rings on the left half (between
// columns j and j + 1 of ring k) and its mirror image on the right.
template <class Fn>
void for_each_fine(const Builder& B, Fn fn) {
  for (int k = fine_first(); k <= fine_last(); ++k)
    for (int j = 0; j < kFineColumns; ++j) fn(k, j, B.fine_at(k, j), B.fine_at(k, kTorsoN - 1 - j));
}

// Each vertex's one-ring: the vertices it shares an edge with.
std::vector<std::set<int>> one_rings(const Builder& B) {
  std::vector<std::set<int>> ring(B.v.size());
  for (const auto& t : B.faces)
    for (int c = 0; c < 3; ++c) {
      ring[static_cast<size_t>(t[static_cast<size_t>(c)])].insert(t[static_cast<size_t>((c + 1) % 3)]);
      ring[static_cast<size_t>(t[static_cast<size_t>(c)])].insert(t[static_cast<size_t>((c + 2) % 3)]);
    }
  return ring;
}

// A finger or the thumb (left hand; the right is its mirror image): a tube of rings grown from a
// loop of the hand's vertices (its base) along `dir`, each ring an ellipse about the axis — half
// `half_width` across the palm, `half_thick` through it — turning from the base loop's own shape
// near the base, and closed by a pole at the tip.
struct DigitPlan {
  Part part = Part::Finger;  // what its vertices are to the rig (toes: Leg, bent by the foot joint)
  Vec3 dir{1, 0, 0};         // the axis, unless `tip` is given
  Vec3 up{0, 1, 0};          // the back of the digit (the nail's side)
  std::optional<Vec3> tip;   // where the pole must be (the middle fingertip: the dactylion); sets dir
  double length = 0;         // from the joint plane to the tip, along the axis (unless `tip`)
  double root = 0;           // x distance from the joint plane (knuckles) to the base loop (fingers)
  double blend = 0.12;       // rings reach the elliptic section this fraction of `length` past the base
  std::vector<double> at;    // ring positions, fractions of the length from the joint plane
  std::vector<double> half_width, half_thick;  // per ring, metres
};

// The trapezius' two rings between the shoulders' top (ring `top`, at the acromion's height
// y_acr) and the neck ring. From the front and from behind the shoulder line falls away from the
// neck in a nearly straight slope that starts just under the neck ring (a curve that flattened
// out toward the acromion left square shoulders; one that rose steeply to the neck ring and bent
// upright there, until 2026-12-07, left a column of neck standing on flat shoulders). From the
// side the upper chest recedes early toward the throat (a front that stayed full up to the
// shoulders' top would fold there, worst on short necks), and the back of the neck curves out
// into the upper back: no collar at the neck's base.
std::array<TorsoRing, 2> trapezius_rings(const TorsoRing& top, const TorsoRing& neck, double y_acr) {
  const double top_front = top.cz + top.df, top_back = top.cz - top.db;
  const double neck_front = neck.cz + neck.df, neck_back = neck.cz - neck.db;
  const double dy = neck.y - y_acr;
  auto between = [](TorsoRing& q, double front, double back) {
    q.cz = 0.5 * (front + back);
    q.df = front - q.cz;
    q.db = q.cz - back;
  };
  TorsoRing s1 = top, s2 = top;
  s1.y = y_acr + kTrapeziusLowAt * dy;
  s1.a = top.a - kTrapeziusLowIn * (top.a - neck.a);
  between(s1, std::lerp(top_front, neck_front, kTrapeziusLowFront), std::lerp(top_back, neck_back, kTrapeziusLowBack));
  s2.y = y_acr + kTrapeziusHighAt * dy;
  // On a short neck (C7 3–4 cm above the acromion) the upper ring at kTrapeziusHighIn folded
  // the neck ring (88° at its front on one woman): there its slope is held to kTrapeziusSlope,
  // but it is never narrower than at kTrapeziusHighInMost (until 2026-12-07, every body's).
  const double wide = top.a - kTrapeziusHighIn * (top.a - neck.a);
  const double narrow = top.a - kTrapeziusHighInMost * (top.a - neck.a);
  s2.a = std::max(neck.a * 1.25, std::min(wide, std::max(narrow, neck.a + kTrapeziusSlope * (neck.y - s2.y))));
  between(s2, std::lerp(top_front, neck_front, kTrapeziusHighFront), std::lerp(top_back, neck_back, kTrapeziusHighBack));
  s1.p = 1.9;
  s2.p = 2.0;
  // Their fronts narrow toward the midline: the trapezius widens the neck's base at the sides and
  // back, and the hollow above the collarbones stays in front. Widened all round, the rings'
  // fronts stood out beside the throat and folded the neck ring there (59° on the typical man).
  s1.front_taper = kTrapeziusLowTaper;
  s2.front_taper = kTrapeziusHighTaper;
  return {s1, s2};
}

struct BodyPlan {  // everything the builder needs, derived from the dimensions
  std::vector<TorsoRing> torso;  // per ring
  std::vector<double> torso_tilt_side, torso_tilt_back;  // per ring: y offsets at the side / back (tilted low ring)
  std::vector<double> torso_tilt_flank;  // per ring: y offset at the side, none up to the bust point (armpit)
  // Rings whose vertices take their shape from the torso profile at their own (tilted) height,
  // so tilting them re-samples the same surface instead of bending it.
  std::vector<bool> torso_resample;
  std::vector<double> torso_pitch;  // per ring: y offset at the back, half of it at the sides (head rings)
  std::vector<double> torso_jaw_lift;  // per ring: y offset at the sides of the face, none at its midline
  std::function<TorsoRing(double)> torso_profile;  // ring parameters at any height
  std::function<double(double)> hip_outline;       // the side's half-breadth from thigh to hip
  std::vector<LegRing> leg;      // per ring index ≥ 1 (index 0 unused)
  // Where ANSUR puts the trochanterion or the gluteal furrow at or below the crotch, the seat's
  // lowest torso rings and the legs' first ring drop at the side / back by these (≤ 0) amounts.
  double seat_drop_side = 0, seat_drop_back = 0;
  std::vector<ArmRing> arm;      // per ring index ≥ 1
  DigitPlan thumb;
  std::array<DigitPlan, kFingerCount> finger;
  std::array<DigitPlan, kToeCount> toe;  // left foot
  double crotch_y = 0, crotch_z = 0;  // the crotch point, under the thighs' centres
  double dactylion_x = 0, arm_y = 0, arm_z = 0;
  double head_top = 0;
  double heel_z = 0;  // the heel's back; the big toe's tip is a foot length from it (plan_toes())
  double hand_length = 0;
};


// A digit's section at m (a fraction of its length) relative to its full section: a quarter
// ellipse over the last tip_fraction of the length, so the tip is round.
double rounded(double m, double tip_fraction) {
  const double m0 = 1 - tip_fraction;
  return m <= m0 ? 1.0 : std::sqrt(std::max(0.0, 1 - std::pow((m - m0) / tip_fraction, 2)));
}

// The knuckles and the webs between the fingers lie on an arc, not a straight line across the
// hand: each finger's base lies behind the middle finger's, the little finger's most (about 1.1
// cm on a 19 cm hand; the index's 1.5 mm, the ring finger's 3.5 mm). How far behind, metres, at
// u across the hand (+1 the index's edge, −1 the little finger's; the middle finger's centre at
// 0.2). Straight, the fingers split from a box along one line.
double knuckle_arc(double u, double hand_length) {
  static const MonotoneCurve arc({-1.0, -0.78, -0.3, 0.2, 0.73, 1.0}, {1.3, 1.1, 0.35, 0.0, 0.15, 0.25});
  return arc(std::clamp(u, -1.0, 1.0)) * 0.01 * hand_length / 0.19;
}

// The knuckles on the back of the hand (+Y, palm down): a rise of 4 mm (on a 19 cm hand) over each
// finger's metacarpal head, 2.6 cm long, on the hand's top only. A fist shows them most. At u
// across the hand (as knuckle_arc()) and height y on `ring`; the rise in metres.
double knuckle_bumps(const ArmRing& ring, double knuckle_x, double u, double y, double hand_length) {
  constexpr std::array<double, 4> kCentre = {0.73, 0.2, -0.3, -0.78}, kHalf = {0.22, 0.21, 0.2, 0.18};  // u across the hand
  const double cm = 0.01 * hand_length / 0.19;
  if (std::abs(ring.x - knuckle_x) >= 1.3 * cm) return 0.0;
  const double top = smoothstep(0.3, 0.8, (y - ring.yc) / ring.ry);
  double rise = 0;
  for (size_t f = 0; f < kCentre.size(); ++f) rise += blob(u - kCentre[f], ring.x - knuckle_x, kHalf[f], 1.3 * cm);
  return 0.4 * cm * top * rise;
}

// The thumb and fingers of the left hand, from the knuckle and web rings (ANSUR has only hand
// length and breadth: the rest are typical proportions). The middle fingertip is the dactylion,
// so hand length and span stay exact; the others' lengths are fractions of the middle finger's,
// each finger takes a share of the hand's breadth, and the outer ones fan out a little.
void plan_digits(const Dims& d, const ArmRing& knuckle, const ArmRing& web, BodyPlan& P) {
  DigitPlan& t = P.thumb;
  t.part = Part::Thumb;
  t.dir = Vec3(0.8, -0.25, 0.52).normalized();  // out, forward and a little under the palm (opposed)
  t.length = 0.36 * d.handl;
  t.blend = 0.25;
  for (double u : kThumbU) {
    // Full at the base (the ball of the thumb), a slight swelling at the knuckle, a rounded tip.
    const double joint = 1 + 0.05 * std::exp(-std::pow((u - kThumbU[kThumbIpRing]) / 0.05, 2));
    const double r = 0.062 * d.handl * (1.15 - 0.35 * u) * joint * rounded(u, 0.3);
    t.at.push_back(u);
    t.half_width.push_back(r);
    t.half_thick.push_back(0.88 * r);
  }
  constexpr std::array<double, kFingerCount> kLength = {0.91, 1.0, 0.95, 0.77};   // × the middle finger's
  constexpr std::array<double, kFingerCount> kYawDeg = {3, 0, -4, -9};           // towards +Z (the thumb)
  constexpr std::array<double, kFingerCount> kShare = {0.27, 0.26, 0.245, 0.225};  // of the hand's breadth
  const double middle = P.dactylion_x - knuckle.x, breadth = 2 * web.rz;
  for (int f = 0; f < kFingerCount; ++f) {
    DigitPlan& g = P.finger[static_cast<size_t>(f)];
    const double yaw = kYawDeg[static_cast<size_t>(f)] * kPi / 180;
    g.dir = Vec3(std::cos(yaw), 0, std::sin(yaw));
    g.length = kLength[static_cast<size_t>(f)] * middle;
    if (f == kMiddle) g.tip = Vec3(P.dactylion_x, P.arm_y, P.arm_z);
    g.root = web.x - knuckle.x;
    const double w0 = 0.5 * kShare[static_cast<size_t>(f)] * breadth;
    for (double m : kFingerM) {
      // Taper to the tip, a slight swelling over the two finger joints, a rounded tip.
      const double knuckles = 1 + 0.05 * (std::exp(-std::pow((m - kFingerM[kPipRing]) / 0.035, 2)) +
                                          std::exp(-std::pow((m - kFingerM[kDipRing]) / 0.03, 2)));
      const double r = w0 * (1 - 0.22 * m) * knuckles * rounded(m, 0.8 * w0 / g.length);
      g.at.push_back(m);
      g.half_width.push_back(r);
      g.half_thick.push_back(0.85 * r);
    }
  }
}

// The back of the foot in profile, at f × the malleolus' height: from the Achilles tendon's back
// (achilles, at the malleolus) down an S-curve (hollow under the tendon, full over the heel bone)
// to the heel bone's fullest back (heel_z, at ring kHeelRing), then rounding forward into the sole
// as a heel does. Falling straight to a sole
// edge at heel_z, it stood square from behind and beside, a boot's heel.
double heel_profile(double f, double achilles, double heel_z, double foot_length) {
  const double f_heel = kFootLevels[kHeelRing];
  if (f >= f_heel) return std::lerp(heel_z, achilles, smoothstep(0.0, 1.0, (f - f_heel) / (1 - f_heel)));
  return heel_z + 0.04 * foot_length * sq(1 - f / f_heel);
}

// The toes of the left foot, grown by build() from their holes in the foot's front (ANSUR has only
// foot length and breadth: the rest are typical proportions). The big toe's tip is the foot
// length's end, as low as the toe's own height allows: its straight distance from the heel
// landmark (on ring kHeelRing, about 1.8 cm up) is exactly the foot length, its distance along the
// floor about 0.4 mm less on a typical foot.
void plan_toes(const Dims& d, BodyPlan& P) {
  const int kf0 = leg_key_ring(kMalleolus) + 1;
  auto ring = [&](int i) -> const LegRing& { return P.leg[static_cast<size_t>(kf0 + i)]; };
  const LegRing& heel_ring = ring(kHeelRing);
  const Vec3 heel(heel_ring.xc, heel_ring.y, P.heel_z);
  constexpr std::array<double, kToeCount> kLength = {0, 0.12, 0.105, 0.09, 0.075};  // × foot length; the big toe's by its tip
  constexpr std::array<double, kToeCount> kYawDeg = {0, 1, 3, 5, 7};                // lateral
  constexpr std::array<double, kToeCount> kWidth = {0.85, 0.8, 0.8, 0.8, 0.8};      // × the hole's half-width
  constexpr std::array<double, kToeCount> kThick = {0.09, 0.065, 0.06, 0.055, 0.05};  // half-thickness, × foot breadth
  const double clearance = 0.0015 * d.footl / 0.26;  // the toes' pads above the floor
  std::array<std::array<double, kLegN>, 3> hole_phi;  // the hole rings' column angles
  for (int i = 0; i < 3; ++i) hole_phi[static_cast<size_t>(i)] = foot_angles(ring(kToeRing + i));
  for (int t = 0; t < kToeCount; ++t) {
    const int c = kToeColumns[static_cast<size_t>(t)];
    Vec3 centre = Vec3::Zero();
    std::array<Vec3, 2> edge;  // on the interior ring, beside the hole
    for (int i = kToeRing; i <= kToeRing + 2; ++i) {
      const auto& phi = hole_phi[static_cast<size_t>(i - kToeRing)];
      for (int k : {c - 1, c, c + 1}) {
        if (i == kToeRing + 1 && k == c) continue;
        const auto q = leg_xz(ring(i), phi[static_cast<size_t>((k + kLegN) % kLegN)]);
        const Vec3 p(q.x(), ring(i).y, q.y());
        centre += p / 8;
        if (i == kToeRing + 1) edge[k < c ? 0 : 1] = p;
      }
    }
    DigitPlan& g = P.toe[static_cast<size_t>(t)];
    g.part = Part::Leg;
    g.blend = 0.2;
    const double w0 = kWidth[static_cast<size_t>(t)] * 0.5 * (edge[1] - edge[0]).norm();
    const double h0 = kThick[static_cast<size_t>(t)] * d.footb;
    const double length = t == 0 ? (1 - kToeWall) * d.footl : kLength[static_cast<size_t>(t)] * d.footl;
    for (double m : kToeAt) {
      const double r = rounded(m, std::min(0.5, 0.9 * w0 / length));
      g.at.push_back(m);
      g.half_width.push_back(w0 * (1 - 0.08 * m) * r);
      g.half_thick.push_back(h0 * (1 - 0.1 * m) * r);
    }
    // The tip as low as it can be with every ring's underside above the floor (the axis runs
    // straight from the hole's centre to the tip).
    double tip_y = clearance;
    for (size_t k = 0; k < kToeAt.size(); ++k)
      tip_y = std::max(tip_y, centre.y() + (clearance + g.half_thick[k] - centre.y()) / kToeAt[k]);
    if (t == 0) {
      const double dy = tip_y - heel.y(), dx = centre.x() - heel.x();
      g.tip = Vec3(centre.x(), tip_y, heel.z() + std::sqrt(d.footl * d.footl - dx * dx - dy * dy));
    } else {
      const double yaw = kYawDeg[static_cast<size_t>(t)] * kPi / 180;
      g.tip = Vec3(centre.x() + length * std::sin(yaw), tip_y, centre.z() + length * std::cos(yaw));
    }
  }
}

// The height of torso ring k's point at angle t (s = sin t, c = cos t): the ring's level, raised
// by its tilts (sides, flanks, back), its pitch (the head's back) and the jaw's lift (the face's
// sides). build() places the rings with it; sculpt() finds where a ring's back ended up.
double torso_point_y(const BodyPlan& P, int k, double s, double c) {
  const size_t i = static_cast<size_t>(k);
  return P.torso[i].y + P.torso_tilt_side[i] * s * s + P.torso_tilt_flank[i] * smoothstep(0.45, 0.95, s * s) +
         P.torso_tilt_back[i] * std::max(0.0, -c) * std::max(0.0, -c) + P.torso_pitch[i] * 0.5 * (1 - c) +
         P.torso_jaw_lift[i] * s * s * smoothstep(-1.0, 0.4, c);
}

BodyPlan plan_body(const Dims& d, Sex sex) {
  BodyPlan P;
  const bool female = sex == Sex::Female;
  const double fem = femininity(sex);
  const double sc = d.S / 1.70;
  const double hs = d.headl / 0.195;  // head scale

  // -- Levels (clamped into a strictly increasing order; see header comment).
  const double y_cr = d.crh;
  const double y_bh = std::max(d.bh, y_cr + 0.010);
  const double y_tr = std::max(d.troch, y_cr + 0.010);
  // The part of each level the clamps above take away: the seat drops there instead (see below).
  P.seat_drop_side = d.troch - y_tr;
  P.seat_drop_back = d.bh - y_bh;
  const double y_bot = y_cr + std::max(0.004, 0.45 * (std::min(y_tr, y_bh) - y_cr));
  const double y_low_ref = std::min(y_tr, y_bh);
  // Buttock circumference / hip breadth level: 3 cm above the higher of the two, less when the
  // navel is close above (ANSUR: as little as 4.6 cm), so the waist ring can sit at the navel and
  // the sides have room to narrow from the hips to the waist.
  const double y_seat = std::max(y_tr, y_bh);
  const double y_hip = y_seat + std::clamp(0.25 * (d.wh - y_seat), 0.005, 0.03 * sc);
  const double y_w = std::max(d.wh, y_hip + 0.012);
  // The iliac crest may lie above or below the navel (ANSUR: −5 to +8 cm). It is a level at the
  // side of the body only: the iliocristale ring's front sits just above the waist ring and its
  // sides are tilted to the crest (see the tilt below), so the crest can pass the navel.
  const double y_ic_side = std::max(d.ilio, y_hip + 0.03);
  const double y_ch = std::max(d.chh, std::max(y_w, y_ic_side) + 0.08);
  // The axilla landmark sits on a ring just under the armpit hole. ANSUR's axilla can lie below
  // the bust point (up to 1.7 cm); then the chest's sides are tilted down to it (see below).
  const double y_ap = std::max(d.axl, y_ch + 0.012);
  const double y_ax = y_ap + 0.006 * sc;  // the armpit hole's bottom
  const double y_acr = std::max(d.acr, y_ax + 0.05);
  const double y_chin = d.S - 0.232 * hs;
  const double y_cv = std::max(d.cerv, y_acr + 0.015);
  // Under C7 first, then over the acromion where there is room for both (on one woman of the
  // development subset C7 is only 1.6 cm over the acromion; std::clamp's bounds crossed there and
  // put the neck ring above the cervicale ring until 2026-11-28).
  const double y_nk = std::min(std::max(std::min(y_cv - 0.006, y_chin - kNeckBelowChin * sc), y_acr + 0.02), y_cv - 0.004);
  const double y_chin_c = std::max(y_chin, y_cv + 0.006);
  const double y_g = d.S - 0.52 * d.headl;
  const double y_nose = y_chin_c + 0.62 * (y_g - y_chin_c) ;
  const double y_mouth = y_chin_c + 0.3 * (y_g - y_chin_c);
  const double y_us_base = std::max(y_w, y_ic_side);
  const double y_us = y_us_base + 0.55 * (y_ch - y_us_base);
  const double y_ic = y_w + (y_us - y_w) / (1 + kTorsoIntervals[kIlio]);  // front of the iliocristale ring

  // -- Torso key rings.
  std::array<TorsoRing, kTorsoKeyCount> K{};
  // Share of the buttock depth in front of the hip ring's centre. Buttocks protrude behind
  // (0.41); when the navel is only a few centimetres above the hip ring (a low, full belly), the
  // hip ring takes the waist ring's split (0.53) instead, or the body would shear forward
  // between the two rings in a visible shelf.
  const double waist_front = 0.53;
  const double hip_front = std::lerp(waist_front, 0.41, std::clamp((y_w - y_hip) / (0.10 * sc), 0.0, 1.0));
  // Hip / buttock ring: hip breadth, buttock depth and circumference (buttocks protrude back).
  {
    TorsoRing& r = K[kHip];
    r.y = y_hip;
    r.cz = 0.0;
    // The cheeks' bumps (on a 24 cm buttock depth; 1 and 2 cm until 2026-12-07, when the ring's
    // own squared corners drew the cheeks as two cushions from behind).
    r.glute = (0.016 + 0.012 * fem) * d.bd / 0.24;
    // The cleft between the buttocks, solved with the ring: the cheeks beside it carry the depth,
    // and the hull (the tape) bridges it. The rings below down to the bottom ring keep it full.
    r.cleft = kCleftDepth * d.bd / 0.24;
    fit_torso_ring(r, d.hb, d.bd, hip_front, d.bc, {.p_min = 1.7, .p_max = 6.0});
  }
  {
    TorsoRing& r = K[kWaist];
    r.y = y_w;
    r.cz = -0.005;
    // The buttocks round off over ~10 cm above the hip ring: a navel closer than that keeps part
    // of them and of their cleft, or they would end in a ridge and the cleft in a notch.
    const double rounded_off = smoothstep(0.0, 0.10 * sc, y_w - y_hip);
    r.glute = K[kHip].glute * (1 - rounded_off);
    r.cleft = K[kHip].cleft * (1 - rounded_off);
    fit_torso_ring(r, d.wb, d.wd, waist_front, d.wc, {.p_min = 1.7, .p_max = 5.0});
  }
  {
    TorsoRing& r = K[kChest];
    r.y = y_ch;
    r.cz = 0.01;
    if (female) { r.bust = 0.085 * d.cd; r.bust_t = 0.72; r.bust_w = 0.44; }
    else if (sex == Sex::Male) { r.bust = 0.025 * d.cd; r.bust_t = 0.65; r.bust_w = 0.5; }
    else { r.bust = 0.05 * d.cd; r.bust_t = 0.7; r.bust_w = 0.42; }
    const ChestFrame relief = chest_frame(sex, sc, y_w, y_us, y_ch, y_ax, y_acr);
    fit_torso_ring(r, d.cb, d.cd, female ? 0.56 : 0.5, d.cc,
                   {.p_min = 1.7, .p_max = kChestP, .growth = Growth::BreadthAndDepth, .p_back_max = kChestBackP,
                    .flare_max = kChestFlareMax, .relief = &relief});  // header: chest
  }
  const double a_sh = std::min(d.biac / 2 - 0.034 * sc, std::max(K[kChest].a * 1.0, d.biac / 2 - 0.05 * sc));
  {
    TorsoRing r = K[kHip];
    r.y = y_bot;
    r.a *= 0.95; r.df *= 0.92; r.db *= 0.9; r.glute *= 0.55; r.p = 2.6;
    K[kBottom] = r;
    r = K[kHip];
    r.y = y_low_ref;
    r.a *= 0.985; r.df *= 0.96; r.db *= 0.97; r.glute *= 0.9;
    K[kLow] = r;
    r = K[kWaist];
    r.y = y_ic;
    K[kIlio] = r;
    r = K[kWaist];  // under the bust: between waist and chest shapes, no bust
    r.y = y_us;
    r.a = std::min(K[kWaist].a, K[kChest].a) * (0.97 - 0.06 * fem);  // the natural waist
    r.cz = 0.0;
    r.df = std::lerp(K[kWaist].df, K[kChest].df, female ? 0.5 : 0.7);
    r.db = std::lerp(K[kWaist].db, K[kChest].db, 0.6);
    r.p = std::min(0.5 * (K[kWaist].p + K[kChest].p), 3.5);
    r.glute = 0;
    r.cleft = 0;
    // The back keeps most of the chest's flare down to here, so from behind it widens nearly
    // straight from the waist to the armpits (at half, it bulged out just under the chest ring).
    r.flare = 0.85 * K[kChest].flare;
    r.back_squareness = 0.5 * K[kChest].back_squareness;
    K[kUnderBust] = r;
    r = K[kChest];
    r.y = y_ax;
    r.a = std::min(K[kChest].a * 1.0, a_sh);
    r.bust *= 0.25;
    r.df = K[kChest].df * (female ? 0.8 : 0.98);
    r.db = K[kChest].db * 0.98;
    r.p = std::max(2.6, K[kChest].p - 0.2);  // no crease at the chest ring's corners
    // The back keeps the chest's squareness and flare up to the armpit: the shoulder blades and
    // the latissimus are as broad there.
    // Under the arm the back stays flared, but within 2.5 cm of the acromion: the arm's root
    // follows the armpit hole's rim out, and the biacromial breadth is exact only while it stays
    // inside the acromion.
    cap_flare(r, d.biac / 2 - 0.025 * sc);
    K[kAxilla] = r;
    K[kArmpit].y = y_ap;  // a level only: its ring takes the profile's shape
    r.y = y_acr;
    r.a = a_sh;
    r.bust = 0;
    r.df = 0.42 * d.cd * (female ? 0.88 : 1.0);
    r.db = 0.42 * d.cd;
    r.cz = -0.005;
    // Round, not boxy, at the shoulders' top: the front and back of the shoulders turn into the
    // arm's root without a corner.
    r.p = 1.8;
    // The upper back is furthest back at the shoulder blades and comes forward above them: the
    // shoulders' top ring stands at least 1 cm in front of the axilla ring's back. Set from the
    // chest depth alone it stood behind it on many women, and the back turned forward into the
    // neck along one ring, a ledge across the back from shoulder to shoulder.
    r.db = std::min(r.db, r.cz - (K[kAxilla].cz - K[kAxilla].db + 0.01 * sc));
    r.flare = r.back_squareness = 0;  // round at the shoulders' top, back and front alike
    K[kHoleTop] = r;
  }
  const double neck_r = d.neckc / (2 * kPi);
  {
    TorsoRing& r = K[kNeck];
    r.y = y_nk;
    // The ring carrying the neck's girth lies at the neck's base. ANSUR measures the girth
    // higher, under the larynx, on a plane across the neck's axis; our sections are level, and
    // the chin lies about as high as C7. The neck leans forward, so a level section through it
    // is a little deeper than wide (MakeHuman's, at the same measurements, 10.4–10.7 cm wide and
    // 13.3–15.0 deep at its narrowest, just under the jaw). At 12 % wider than a circle of its
    // girth and 6 % shallower (until the evening of 2026-11-29) the neck was a broad column from
    // the shoulders to the jaw, which the chin ring, no narrower than the neck, widened too: from
    // the front a thick neck under a square jaw.
    r.a = neck_r * 0.98; r.df = neck_r * 1.00; r.db = neck_r * 1.08; r.p = 2.2;
    std::vector<Eigen::Vector2d> pts = torso_polygon(r);
    const double s = d.neckc / convex_hull_perimeter(pts);
    r.a *= s; r.df *= s; r.db *= s;
    // Where the neck stands on the shoulders' top: the depth the neck leaves free there is shared
    // 60 : 40 between the sternal notch in front and the trapezius behind.
    const TorsoRing& top = K[kHoleTop];
    const double slack = std::max(0.0, (top.df + top.db) - (r.df + r.db));
    r.cz = top.cz + top.df - 0.6 * slack - r.df;
    const auto [s1, s2] = trapezius_rings(top, r, y_acr);
    K[kShoulder1] = s1;
    K[kShoulder2] = s2;
  }
  {
    const double hb2 = d.headb / 2, hl2 = d.headl / 2;
    // The head sits forward of the neck's base: the neck leans forward from the shoulders, so in
    // profile the occiput stands about over C7 and the upper back behind both. With the head
    // 2 cm further back (before 2026-11-28) the neck stood upright and the skull overhung it.
    const double head_cz = K[kNeck].cz + 0.042 * hs;
    TorsoRing r = K[kNeck];
    r.y = y_cv;
    // Above the neck ring the neck narrows toward the jaw (by 10 %; 5 % until the evening of
    // 2026-11-29), and C7 stands about a centimetre (18 % of the neck ring's back) in front of the
    // neck ring's back: the back of the neck leans forward from its base through C7 into the
    // nape. With C7 only 5 % in front (before 2026-11-29) the back of the neck rose nearly
    // upright to C7 and turned forward there, and from behind its lower part stood lit under the
    // nape's shade: a collar.
    r.a *= 0.90; r.db *= 0.82; r.df *= 0.99;
    // The neck's front leans forward up to the floor of the mouth: the cervicale ring (C7 lies
    // at most 6 mm under the chin ring, often more) takes its front kJawFloorFront of the way
    // from its own to the chin's, times the share of the height (neck ring to chin ring) it lies
    // at. Its back (C7) and sides stay (moving its centre forward sheared the neck's sides until
    // their faces crossed). With its front at the neck's (before 2026-11-28) the neck's front
    // stood upright to a level shelf under the chin, 6–7 cm deep; a larger share, for a straight
    // slope to the chin, folded the throat at the neck ring (docs/mannequin.md).
    {
      const double front0 = r.cz + r.df, chin_front = head_cz + kChinFront * hl2 + kChinBump * hs;
      const double u = std::clamp((y_cv - y_nk) / std::max(1e-6, y_chin_c - y_nk), 0.0, 1.0);
      r.df += kJawFloorFront * u * std::max(0.0, chin_front - front0);
    }
    K[kCervicale] = r;
    r.y = y_chin_c;
    r.cz = head_cz;
    // The chin ring reaches from the chin back to the neck's back (its back is then redrawn by
    // the nape's profile, below); it is no narrower than the neck under it.
    r.a = std::max(0.78 * hb2, K[kCervicale].a); r.db = K[kNeck].db + (head_cz - K[kNeck].cz) + 0.002 * hs; r.df = kChinFront * hl2; r.p = 2.2;
    r.chin = kChinBump * hs;
    // The jaw narrows toward the chin: a U from the front, not a box. By a half near the midline
    // it came to a point; a man's chin is broader and squarer than a woman's.
    r.front_taper = std::lerp(0.30, 0.38, fem);
    K[kChin] = r;
    // The lower face stands nearly upright under the glabella, as in a real profile (at 0.84 and
    // 0.78 of the half-length the face sloped back to a receding chin).
    r.y = y_mouth; r.a = std::max(0.8 * hb2, r.a + 0.003 * hs);  // never narrower than the jaw below
    r.df = 0.90 * hl2;
    r.db = 0.35 * (K[kNeck].db + (head_cz - K[kNeck].cz)) + 0.65 * 0.82 * hl2;
    r.chin = 0.004 * hs;
    r.front_taper = 0.22;
    K[kMouth] = r;
    TorsoRing g;
    g.y = y_g; g.cz = head_cz;
    fit_torso_ring(g, d.headb, d.headl, 0.48, d.headc, {.p_min = 1.8, .p_max = 10.0});
    K[kGlabella] = g;
    // At the nose the skull's back is nearly as full as at the glabella (the occiput rounds off
    // below it). That back only places the nape's hollow: the profile from the nape to the
    // occiput (below) redraws the backs of the rings from C7 up to the glabella ring.
    r.y = y_nose; r.a = 0.92 * hb2; r.df = 0.91 * hl2; r.db = 0.93 * g.db; r.p = 0.5 * (2.2 + g.p);
    r.chin = 0; r.nose = 0;  // the nose itself: sculpt()
    r.front_taper = 0.15;
    K[kNose] = r;
  }

  // Ring levels between keys, then monotone interpolation of every parameter over y.
  std::vector<double> ky, ka, kdf, kdb, kcz, kp, kbust, kglute, kcleft, knose, kchin, kfront_taper, kflare, kback_squareness;
  for (int key = 0; key < kTorsoKeyCount; ++key) {
    // The iliocristale ring is a level, not a shape: a duplicate knot there would flatten the
    // profile into a visible band.
    if (key == kIlio || key == kArmpit) continue;
    const TorsoRing& r = K[static_cast<size_t>(key)];
    ky.push_back(r.y); ka.push_back(r.a); kdf.push_back(r.df); kdb.push_back(r.db); kcz.push_back(r.cz);
    kp.push_back(r.p); kbust.push_back(r.bust); kglute.push_back(r.glute); kcleft.push_back(r.cleft);
    knose.push_back(r.nose); kchin.push_back(r.chin); kfront_taper.push_back(r.front_taper); kflare.push_back(r.flare);
    kback_squareness.push_back(r.back_squareness);
  }
  // A knot on the dome (as the dome rings below compute it) gives the head's profile a level
  // tangent at the glabella ring, its widest: the face rings meet the dome without a band.
  {
    const TorsoRing r = dome_ring(K[kGlabella], d.S, hs, dome_angle(0.3));
    ky.push_back(r.y); ka.push_back(r.a); kdf.push_back(r.df); kdb.push_back(r.db);
    kcz.push_back(r.cz); kp.push_back(r.p); kbust.push_back(0); kglute.push_back(0); kcleft.push_back(0);
    knose.push_back(0); kchin.push_back(0); kfront_taper.push_back(0); kflare.push_back(0); kback_squareness.push_back(0);
  }
  // The bust needs its own profile: fuller below the apex, fading toward the axilla.
  const MonotoneCurve ca(ky, ka), cdf(ky, kdf), cdb(ky, kdb), ccz(ky, kcz), cp(ky, kp), cglute(ky, kglute),
      ccleft(ky, kcleft), cnose(ky, knose), cchin(ky, kchin), cfront_taper(ky, kfront_taper), cflare(ky, kflare), cback_squareness(ky, kback_squareness);
  const double bust = K[kChest].bust;
  const MonotoneCurve cbust({std::min(y_ic, y_ch - 0.1 * sc), y_ch - 0.085 * sc, y_ch - 0.045 * sc, y_ch, y_ch + 0.05 * sc, y_ax, y_acr},
                            {0, 0.05 * bust, 0.7 * bust, bust, 0.6 * bust, 0.25 * bust, 0});
  const int nt = torso_ring_count();
  P.torso.resize(static_cast<size_t>(nt));
  P.torso_tilt_side.assign(static_cast<size_t>(nt), 0.0);
  P.torso_tilt_back.assign(static_cast<size_t>(nt), 0.0);
  P.torso_tilt_flank.assign(static_cast<size_t>(nt), 0.0);
  P.torso_resample.assign(static_cast<size_t>(nt), false);
  P.torso_pitch.assign(static_cast<size_t>(nt), 0.0);
  P.torso_jaw_lift.assign(static_cast<size_t>(nt), 0.0);
  const double bust_t = K[kChest].bust_t, bust_w = K[kChest].bust_w;
  P.torso_profile = [=](double y) {
    TorsoRing r;
    r.y = y; r.a = ca(y); r.df = cdf(y); r.db = cdb(y); r.cz = ccz(y); r.p = cp(y);
    r.bust = cbust(y); r.bust_t = bust_t; r.bust_w = bust_w;
    r.glute = cglute(y); r.cleft = ccleft(y); r.nose = cnose(y); r.chin = cchin(y); r.front_taper = cfront_taper(y);
    r.flare = cflare(y);
    r.back_squareness = cback_squareness(y);
    return r;
  };
  for (int key = 0; key + 1 < kTorsoKeyCount; ++key) {
    const int k0 = torso_key_ring(key), n = kTorsoIntervals[static_cast<size_t>(key)];
    for (int i = 0; i < n; ++i) {
      const double y = K[key].y + (K[key + 1].y - K[key].y) * i / n;
      TorsoRing r = P.torso_profile(y);
      if (i == 0 && key != kIlio && key != kArmpit) { r = K[key]; if (key > kChest && key < kNeck) r.bust = cbust(y); }
      P.torso[static_cast<size_t>(k0 + i)] = r;
    }
  }
  const int kg = torso_key_ring(kGlabella);
  P.torso[static_cast<size_t>(kg)] = K[kGlabella];
  // The tilted low ring reaches trochanterion height at the sides and buttock height at the back.
  {
    // The rings up to the hip ring share a fading tilt so no ring's side or back rises above
    // the next ring's.
    const int kl = torso_key_ring(kLow), kh = torso_key_ring(kHip);
    for (int k = kl; k < kh; ++k) {
      const double fade = 1.0 - static_cast<double>(k - kl) / (kh - kl);
      P.torso_tilt_side[static_cast<size_t>(k)] = (y_tr - y_low_ref) * fade;
      P.torso_tilt_back[static_cast<size_t>(k)] = (y_bh - y_low_ref) * fade;
    }
    // A seat lower than the clamps allow: the rings from the bottom up to the low ring (whose side
    // carries the trochanterion and whose back the gluteal furrow) drop together, keeping their
    // spacing, and so do the legs' first ring and the crotch bridge's back (in build()).
    for (int k = 0; k <= kl; ++k) {
      P.torso_tilt_side[static_cast<size_t>(k)] += P.seat_drop_side;
      P.torso_tilt_back[static_cast<size_t>(k)] += P.seat_drop_back;
    }
  }
  // The iliac crest: the rings' sides rise evenly from the hip ring through the crest to the
  // under-bust ring while their fronts keep their levels (the waist ring's front is the navel).
  // The tilted rings re-sample the same profile, so horizontal sections (the waist's breadth,
  // depth and girth at the navel) are those of the untilted surface.
  {
    const int kh = torso_key_ring(kHip), ki = torso_key_ring(kIlio), ku = torso_key_ring(kUnderBust);
    for (int k = kh + 1; k < ku; ++k) {
      const double side = k <= ki ? std::lerp(y_hip, y_ic_side, static_cast<double>(k - kh) / (ki - kh))
                                  : std::lerp(y_ic_side, y_us, static_cast<double>(k - ki) / (ku - ki));
      P.torso_tilt_side[static_cast<size_t>(k)] = side - P.torso[static_cast<size_t>(k)].y;
      P.torso_resample[static_cast<size_t>(k)] = true;
    }
  }
  // An axilla below the clamp: the rings from the under-bust ring up to the armpit ring are
  // compressed at the sides toward the under-bust level (bust points and midlines stay), so the
  // armpit ring's side reaches the axilla. They re-sample the same profile, so the chest's
  // horizontal section at the bust point keeps its breadth and girth.
  if (d.axl < y_ap) {
    const int ku = torso_key_ring(kUnderBust), kap = torso_key_ring(kArmpit);
    for (int k = ku + 1; k <= kap; ++k) {
      const double y = P.torso[static_cast<size_t>(k)].y;
      P.torso_tilt_flank[static_cast<size_t>(k)] = (d.axl - y_ap) * (y - y_us) / (y_ap - y_us);
      P.torso_resample[static_cast<size_t>(k)] = true;
    }
  }
  // The lower head leans back: the rings from the chin to the nose pitch up behind, so the jaw
  // runs from the chin up to the back of the skull and the back of the neck rises to the occiput
  // (horizontal rings would leave the head on a flat shelf). The glabella ring, which carries the
  // head's breadth, length and circumference, stays level; so does the cervicale ring's back.
  {
    const double span = y_g - y_chin_c;
    const int kc = torso_key_ring(kCervicale), kch = torso_key_ring(kChin), kgl = torso_key_ring(kGlabella);
    // Per key ring: the pitch (back raised) and the jaw's lift (sides raised; see build()).
    struct Key { int ring; double pitch, jaw; };
    const std::array<Key, 4> keys = {{{kc, 0.0, 0.0}, {kch, 0.30 * span, kJawLift * span},
                                      {torso_key_ring(kMouth), 0.18 * span, 0.4 * kJawLift * span},
                                      {torso_key_ring(kNose), 0.06 * span, 0.0}}};
    // Smooth curves through the keys, over the rings' levels: interpolated linearly, the pitch and
    // the lift changed slope at the chin ring, and the side of the neck showed a line there from
    // the jaw's angle back. Into the level glabella ring both ease out (zero slope), or the back
    // and sides of the head would fold along that ring.
    std::vector<double> key_y, kpitch, kjaw;
    for (const Key& key : keys) {
      key_y.push_back(P.torso[static_cast<size_t>(key.ring)].y);
      kpitch.push_back(key.pitch);
      kjaw.push_back(key.jaw);
    }
    for (double above : {0.0, span}) {
      key_y.push_back(P.torso[static_cast<size_t>(kgl)].y + above);
      kpitch.push_back(0.0);
      kjaw.push_back(0.0);
    }
    const MonotoneCurve pitch(key_y, kpitch), jaw(key_y, kjaw);
    for (int k = kc; k < kgl; ++k) {
      P.torso_pitch[static_cast<size_t>(k)] = pitch(P.torso[static_cast<size_t>(k)].y);
      P.torso_jaw_lift[static_cast<size_t>(k)] = jaw(P.torso[static_cast<size_t>(k)].y);
    }
  }
  // The nape and the occiput: the backs of the rings from the cervicale up to the glabella ring
  // follow one smooth profile. From C7 the back of the neck leans forward into the nape's hollow,
  // halfway up to the nose ring's back and 1.2 head-centimetres in front of both (a monotone cubic
  // through the ring under C7, C7 and the hollow); from the hollow the skull rounds out behind to
  // the glabella ring's back, the head's longest point, on a quintic that meets the neck's curve
  // and the dome in slope and second derivative. Before (2026-11-28) the back
  // of the neck stood straight from the shoulders into the skull, a pipe; until 2026-11-29 the
  // profile ended at the nose ring, whose own back and the glabella ring's met it with a kink,
  // and the back of the head showed a band at each (its curvature went from −18°/cm to +10°/cm
  // at the nose ring on the mean man, and from −6°/cm to 0 at the glabella ring). A monotone
  // cubic carried up to the glabella ring (tried before) reshaped the skull's side behind the
  // ears: on some women the ear's rim stood less than 1 mm beyond its bowl. Interpolated between
  // the key rings, the chin ring's back stood out under the skull, a helmet's rim.
  {
    const int kc = torso_key_ring(kCervicale), kn = torso_key_ring(kNose), kgl = torso_key_ring(kGlabella);
    auto back_y = [&](int k) { return torso_point_y(P, k, 0, -1); };
    auto back_z = [&](int k) { return P.torso[static_cast<size_t>(k)].cz - P.torso[static_cast<size_t>(k)].db; };
    const double y_nape = std::lerp(back_y(kc), back_y(kn), 0.5);
    const double z_nape = std::max(back_z(kc), back_z(kn)) + 0.012 * hs;
    // The neck's curve is level at the hollow: a last knot as deep as the hollow, above it, says so.
    const MonotoneCurve neck({back_y(kc - 1), back_y(kc), y_nape, y_nape + 0.01 * hs}, {back_z(kc - 1), back_z(kc), z_nape, z_nape});
    // Second derivatives by finite differences: under the hollow on the neck's curve, over the
    // glabella ring on the dome's (by height u over it; the dome's back has no pitch).
    const double e = 1e-5 * hs;
    const double neck_curvature = (neck(y_nape) - 2 * neck(y_nape - e) + neck(y_nape - 2 * e)) / (e * e);
    const double dome_h = d.S - K[kGlabella].y, du = e / dome_h;
    auto dome_back_z = [&](double u) {
      const TorsoRing r = dome_ring(K[kGlabella], d.S, hs, dome_angle(u));
      return r.cz - r.db;
    };
    const double dome_curvature = (dome_back_z(0) - 2 * dome_back_z(du) + dome_back_z(2 * du)) / (e * e);
    // Bounded so the quintic cannot swing back past its ends: with level ends it stays monotone
    // while each end's h²|z''| / |Δz| is at most kOcciputMaxBend (checked numerically over the
    // whole square; with the other end's at 0 it turns back past 20.5). No development body
    // reaches it; some men's necks pass 12.
    const double h = back_y(kgl) - y_nape, bend = kOcciputMaxBend * std::abs(back_z(kgl) - z_nape) / (h * h);
    const QuinticEnd hollow{y_nape, z_nape, 0.0, std::clamp(neck_curvature, -bend, bend)};
    const QuinticEnd occiput{back_y(kgl), back_z(kgl), 0.0, std::clamp(dome_curvature, -bend, bend)};
    for (int k = kc + 1; k < kgl; ++k) {
      const double y = back_y(k);
      P.torso[static_cast<size_t>(k)].db = P.torso[static_cast<size_t>(k)].cz - (y <= y_nape ? neck(y) : quintic_hermite(hollow, occiput, y));
    }
  }
  // Dome: a quarter-superellipse from the glabella ring to the vertex (dome_ring).
  P.head_top = d.S;
  for (int i = 1; i <= kDomeRings; ++i)
    // Angles bunched toward the glabella ring: evenly spaced ones would leave the first dome ring
    // 2 cm above a face whose rings are 5 mm apart, and the forehead shades a line there.
    P.torso[static_cast<size_t>(kg + i)] =
        dome_ring(K[kGlabella], d.S, hs, (kPi / 2) * std::pow(i / (kDomeRings + 0.6), 1.25));
  P.crotch_y = y_cr;

  // -- Legs (left; the right leg mirrors it).
  {
    std::array<LegRing, kLegKeyCount> L{};
    const double y_kn = d.knee, y_ml = d.mall;
    auto splay = [&](double at) { return splay_offset(at, y_cr, y_ml, sc); };  // splay_legs(), later
    L[kLegTop].y = y_cr - 0.008 * sc;
    // The thigh ring stays below the legs' first ring where that drops under a low seat.
    const double y_th = std::min(y_cr - 0.03 * sc, L[kLegTop].y + std::min(P.seat_drop_side, P.seat_drop_back) - 0.012 * sc);
    L[kThigh].y = y_th;
    // ANSUR takes the lower thigh's girth just above the knee, over the kneecap's top. With its
    // ring 11 cm over the kneecap's middle (until 2026-11-29) the thigh narrowed to that girth
    // far too high: on the mean man it lost 9 cm of girth by mid-thigh against MakeHuman's, and
    // heavy bodies stood on thin, tapering thighs. At 4 cm the heaviest thighs buried the
    // kneecap (one woman's stood 1.3 mm out of the thigh's front; the check asks 3 mm).
    L[kLowerThigh].y = y_kn + kLowerThighOverKnee * sc;
    L[kKnee].y = y_kn;
    L[kCalf].y = y_kn - 0.36 * (y_kn - y_ml);
    L[kAnkle].y = y_ml + 0.42 * (L[kCalf].y - y_ml) * 0.35;
    L[kMalleolus].y = y_ml;
    // Thigh: as wide as fits beside the other thigh and inside the hip outline.
    {
      LegRing& r = L[kThigh];
      // Two thighs side by side often need more room than the hips give: squeeze them deeper.
      const double half_hip = K[kBottom].a;
      for (double ratio = 1.05; ratio < 1.8; ratio += 0.05) {
        r.al = r.am = 1; r.bf = ratio; r.bb = ratio * 1.05; r.p = 2.3;
        fit_leg_circumference(r, d.thighc);
        if (r.al + r.am <= half_hip - 0.004) break;
      }
      r.xc = std::max(r.am + 0.004, half_hip - r.al * 1.02);
      // A little in front of the middle of the hip section: ANSUR's proximal thigh girth makes
      // the thigh nearly as deep as the buttocks, and centred under them its back was flush with
      // theirs, so from the side the buttocks did not stand out over the thighs at all.
      r.zc = K[kHip].cz + (hip_front - 0.5 + kThighForward) * d.bd;
    }
    // medial: the inner half-breadth is 1 + medial, the outer 1 − medial (shares, before the fit).
    auto make = [&](LegRing& r, double c, double xc, double zc, double depth_ratio, double calf, double medial = 0) {
      r.al = 1 - medial; r.am = 1 + medial; r.bf = depth_ratio; r.bb = depth_ratio; r.p = 2.2; r.calf = calf;
      fit_leg_circumference(r, c);
      r.xc = std::max(xc, r.am + kLegMidlineGap);
      r.zc = zc;
    };
    make(L[kLowerThigh], d.lthighc, 0.55 * L[kThigh].xc + 0.04 * sc, 0.0, 1.0, 0);
    // (The lower thigh's ring here is where make() put it: keep_knee_under_hip(), below, may still
    // move the leg in under a narrow hip, and the outline then leaves the thigh a little flatter
    // than the leg falls below it; noticed 2026-12-07, left so.)
    // The body's side outline from the thigh ring up to the hip ring: one cubic leaving the thigh
    // at the slope the leg has below it and arriving flat at the hip's maximum breadth, so hips
    // flow into thighs with no shoulder at the crotch.
    {
      const LegRing &th = L[kThigh], &lt = L[kLowerThigh];
      const double x0 = th.xc + th.al, x1 = K[kHip].a, h = y_hip - th.y;
      const double secant = (x1 - x0) / h;
      const double m0 = secant <= 0 ? 0.0 : std::clamp((x0 - (lt.xc + lt.al)) / (th.y - lt.y), 0.0, 3 * secant);
      P.hip_outline = [=](double y) {
        const double u = std::clamp((y - th.y) / h, 0.0, 1.0), u2 = u * u, u3 = u2 * u;
        return (2 * u3 - 3 * u2 + 1) * x0 + (u3 - 2 * u2 + u) * h * m0 + (-2 * u3 + 3 * u2) * x1;
      };
    }
    {
      // Just below the crotch the thigh still carries the hip's flesh: a fuller ring whose outer
      // side follows the hip outline.
      const LegRing& r = L[kThigh];
      LegRing& t = L[kLegTop];
      const double y_keep = t.y;
      t = r;
      t.y = y_keep;
      t.al = std::max(r.al, P.hip_outline(t.y) - t.xc);
      t.bb *= 1.03;
      t.am = std::min(t.am * 1.05, t.xc - kLegMidlineGap);
    }
    // The knee (no ANSUR girth): 0.9 of the lower thigh's girth, but no fuller than the calf, or
    // from the front the leg ran from the knee to the ankle as a cone (on about one body in eight).
    make(L[kKnee], std::min(0.97 * d.lthighc * 0.93, d.calfc), 0.5 * L[kThigh].xc + 0.04 * sc, 0.008, 1.10, 0);
    make(L[kCalf], d.calfc, 0.45 * L[kThigh].xc + 0.042 * sc, -0.006, 0.92, 0.25, 0.07);
    make(L[kAnkle], d.anklec, 0.42 * L[kThigh].xc + 0.04 * sc, -0.012, 1.05, 0);
    make(L[kMalleolus], d.anklec * 1.12, L[kAnkle].xc, -0.012, 0.95, 0);
    keep_knee_under_hip(L, splay);
    std::vector<double> y, xc, zc, al, am, bf, bb, pp, calf;
    for (int i = kLegKeyCount - 1; i >= 0; --i) {  // increasing y
      const LegRing& r = L[static_cast<size_t>(i)];
      y.push_back(r.y); xc.push_back(r.xc); zc.push_back(r.zc); al.push_back(r.al); am.push_back(r.am);
      bf.push_back(r.bf); bb.push_back(r.bb); pp.push_back(r.p); calf.push_back(r.calf);
    }
    const MonotoneCurve cy(y, y), cxc(y, xc), czc(y, zc), cal(y, al), cam(y, am), cbf(y, bf), cbb(y, bb), cpp(y, pp), ccalf(y, calf);
    P.leg.resize(static_cast<size_t>(leg_ring_count()));
    for (int key = 0; key + 1 < kLegKeyCount; ++key) {
      const int k0 = leg_key_ring(key), n = kLegIntervals[static_cast<size_t>(key)];
      for (int i = 0; i < n; ++i) {
        const double yy = L[key].y + (L[key + 1].y - L[key].y) * i / n;
        LegRing r{yy, cxc(yy), czc(yy), cal(yy), cam(yy), cbf(yy), cbb(yy), cpp(yy), ccalf(yy)};
        if (i == 0) r = L[key];
        if (key == kThigh && i > 0) thigh_fullness(r, L[kThigh], L[kLowerThigh], static_cast<double>(i) / n, splay(yy) - splay(L[kThigh].y));
        if (key == kCalf && i > 0) shin_taper(r, L[kCalf], L[kAnkle], static_cast<double>(i) / n);
        P.leg[static_cast<size_t>(k0 + i)] = r;
      }
    }
    P.leg[static_cast<size_t>(leg_key_ring(kMalleolus))] = L[kMalleolus];
    // The torso's bottom ring hugs the two thighs, so hips flow into legs without a ledge.
    {
      const LegRing& t = L[kLegTop];
      TorsoRing& b = P.torso[0];
      b.a = std::max(t.xc + t.al, P.hip_outline(b.y));
      b.glute = 0;
      b.p = 2.4;
      // Depths such that, above the thigh's centre line (x = xc), the ring reaches the thigh's
      // front and back: there the superellipse is at |cos t|^(2/p) of its full depth.
      const double sn = std::pow(std::clamp(t.xc / b.a, 0.0, 0.95), b.p / 2);
      const double cf = std::pow(std::sqrt(1 - sn * sn), 2 / b.p);
      const double t_thigh = std::asin(sn);  // the ring's angle above the thigh's centre line
      // Not deeper at the centre than the hip ring or the thighs themselves: a bottom ring that
      // bulges past both neighbours reads as a band where hips meet thighs.
      const int kh = torso_key_ring(kHip);
      const TorsoRing& h = P.torso[static_cast<size_t>(kh)];
      const double reach_front = t.zc + t.bf - b.cz, reach_back = b.cz - (t.zc - t.bb);
      // In front, one bump over each thigh (the bust bumps' shape) rather than a deeper ring: the
      // lower belly then meets the thighs over their fronts and dips between them, instead of
      // overhanging both in a horizontal crease.
      b.df = std::max(0.02, std::min(0.98 * reach_front, std::max(h.df, reach_front)));
      b.bust_t = t_thigh;
      b.bust_w = 0.35;
      // Outward of the thigh's centre the bump stays full longer, so the belly's lowest rings reach
      // the thigh's front-lateral curve: narrower, they fell behind it and the hips met the thighs
      // in a level groove across the front.
      b.bust_w_out = 0.7;
      b.bust = std::max(0.0, reach_front - b.df * cf);
      b.db = std::max(0.02, std::min(0.98 * reach_back, std::max(h.db, reach_back)));
      // The buttock cheeks end over the backs of the thighs (the gluteal fold), never in front
      // of them: a thigh bulging out under the buttock reads as a band.
      {
        const double gap = (b.cz - b.db * cf) - (t.zc - t.bb) + 0.003;
        const double bump = glute_bump(kPi - t_thigh);
        b.glute = std::max(0.0, gap / bump);
      }
      // Rings between the bottom and the hip ring: the sides follow the hip outline. The front
      // blends with zero slope at both ends (thighs below, the hip above), so its profile has no
      // kink at either ring. The back leaves the bottom ring steeply and stays full well below
      // the hip ring, and the cheeks' bumps rise only from the gluteal furrow's ring up: the
      // buttocks round under into the fold over the thighs (a smooth step behind too drew an
      // S-slope with no fold).
      const int kl = torso_key_ring(kLow);  // its back is the gluteal furrow
      for (int k = 1; k < kh; ++k) {
        TorsoRing& r = P.torso[static_cast<size_t>(k)];
        const double u = (r.y - b.y) / (h.y - b.y), e = u * u * (3 - 2 * u);
        auto round_under = [](double share) { return 1 - std::pow(1 - share, kSeatRoundUnder); };
        const double e_back = round_under(u);
        const double e_cheek = round_under(std::clamp(static_cast<double>(k - kl) / (kh - kl), 0.0, 1.0));
        r.a = P.hip_outline(r.y + P.torso_tilt_side[static_cast<size_t>(k)]); r.df = std::lerp(b.df, h.df, e); r.db = std::lerp(b.db, h.db, e_back);
        r.cz = std::lerp(b.cz, h.cz, e); r.p = std::lerp(b.p, h.p, e); r.glute = std::lerp(b.glute, h.glute, e_cheek);
        r.cleft = std::lerp(b.cleft, h.cleft, e);
        r.bust = std::lerp(b.bust, 0.0, e); r.bust_t = b.bust_t; r.bust_w = b.bust_w; r.bust_w_out = b.bust_w_out;
      }
      P.crotch_z = std::clamp(t.zc, b.cz - 0.5 * b.db, b.cz + 0.5 * b.df);
    }
    // Foot rings: footprint outline growing from the ankle ring as y goes down. Stored as
    // LegRing with centre at the ball line; bf/bb = front/back lengths, al/am = half-widths.
    const double fl = d.footl, fb = d.footb;
    const double z_ank = L[kMalleolus].zc;
    P.heel_z = z_ank - 0.24 * fl;
    const LegRing& m = L[kMalleolus];
    const int kf0 = leg_key_ring(kMalleolus) + 1;
    // The top of the foot in profile: the dorsum rising from the toes' wall to the front of the
    // ankle. The toes (plan_toes()) leave that wall, which stands from the holes' top ring down;
    // below the holes the ball's pad rounds back under the toes, which overhang it.
    const double z_wall = P.heel_z + kToeWall * fl;
    const MonotoneCurve instep({0.0, 0.12, 0.18, 0.29, 0.42, 0.58, 0.78, 1.0}, {1.0, 1.0, 1.0, 1.0, 0.8, 0.5, 0.18, 0.0});
    for (size_t i = 0; i <= kFootLevels.size(); ++i) {
      const double f = i < kFootLevels.size() ? kFootLevels[i] : 0.0;
      const double yy = f * y_ml;
      const double u = 1 - f;  // 0 at the malleolus, 1 at the sole
      // Front reach follows the instep down to the toes' wall.
      const double front = std::lerp(z_ank + m.bf, z_wall, instep(f)) - (f <= kFootLevels[kFootBreadthRing] ? 0.003 * fl / 0.26 : 0.0);
      const double back = heel_profile(f, z_ank - m.bb, P.heel_z, fl);
      const double ball = 0.7;
      const double cz = back + std::lerp(0.5, ball, std::pow(u, 1.5)) * (front - back);
      LegRing r;
      r.y = yy;
      r.zc = cz;
      r.bf = front - cz;
      r.bb = cz - back;
      r.al = std::lerp(m.al, fb * 0.52, std::pow(u, 1.3));
      r.am = std::lerp(m.am, fb * 0.48, std::pow(u, 1.3));
      r.xc = m.xc + std::lerp(0.0, 0.004, u);
      r.p = std::lerp(2.2, 2.6, u);
      // Towards the sole the front squares off (the toes' broad front) and slants back laterally.
      r.p_front = std::lerp(2.2, 3.4, u * u);
      r.toe_slant = 0.04 * fl * u * u;
      // The footprint: its back half narrows toward the heel (by up to 30 % at the sole), the arch
      // drawn in on the inside; a symmetric outline made the heel as broad as the ball, a slipper
      // from behind. The breadth and length, at c = 0 and c = ±1, are untouched.
      r.heel = 0.3 * std::pow(u, 1.5);
      r.arch = 0.15 * u * u;
      r.toe_spacing = 1 - smoothstep(kFootLevels[kToeRing], 0.65, f);
      if (i == kFootLevels.size()) {  // the sole: a little inside the ring above, on the floor
        const LegRing& up = P.leg[static_cast<size_t>(kf0 + static_cast<int>(i) - 1)];
        r = up;
        r.y = 0;
        r.al -= 0.004; r.am -= 0.004; r.bf -= 0.006; r.bb -= 0.006;
      }
      if (static_cast<int>(i) == kFootBreadthRing) {  // exact breadth on this ring (the ball)
        r.al = r.am = fb / 2;
        const double c0 = P.heel_z + ball * fl;
        r.zc = c0; r.bf = front - c0; r.bb = c0 - back;
      }
      P.leg[static_cast<size_t>(kf0 + static_cast<int>(i))] = r;
    }
    // The toes' wall: the rings around their holes take the breadth ring's front outline (3 mm
    // ahead of it), so the wall stands upright and no lower ring juts out under the toes; their
    // sides draw in a little toward the top, more on the lateral side, which is low on a foot.
    const LegRing& wall = P.leg[static_cast<size_t>(kf0 + kFootBreadthRing)];
    for (int i = kToeRing; i < kFootBreadthRing; ++i) {
      LegRing& r = P.leg[static_cast<size_t>(kf0 + i)];
      const double back = r.zc - r.bb, draw_in = 0.004 * fb / 0.1 * std::pow((kFootBreadthRing - i) / 3.0, 2);
      r.zc = wall.zc; r.bf = wall.bf + 0.003 * fl / 0.26; r.bb = r.zc - back;
      r.xc = wall.xc; r.al = wall.al - draw_in; r.am = wall.am - 0.4 * draw_in; r.p_front = wall.p_front; r.toe_slant = wall.toe_slant;
    }
  }

  plan_toes(d, P);

  // -- Arms (left). Span, biacromial breadth and hand length exact; segments share one scale.
  {
    std::array<ArmRing, kArmKeyCount> A{};
    const double half_b = d.biac / 2;
    // Hole extent on the torso: computed from the rings that carry it.
    const int kax = torso_key_ring(kAxilla);
    double hole_xmax = 0, hole_zmin = 1e9, hole_zmax = -1e9;
    for (int k = kax; k <= kax + kHoleRows; ++k)
      for (int j = kHoleJ0; j <= kHoleJ1; ++j) {
        const auto q = torso_xz(P.torso[static_cast<size_t>(k)], 2 * kPi * j / kTorsoN);
        hole_xmax = std::max(hole_xmax, q.x());
        hole_zmin = std::min(hole_zmin, q.y());
        hole_zmax = std::max(hole_zmax, q.y());
      }
    const double zc0 = 0.5 * (hole_zmin + hole_zmax);
    P.arm_z = zc0;
    // The root ring follows the squarish armpit hole; the deltoid then rounds and swells the
    // shoulder (front and back) before the upper arm narrows.
    A[kRoot] = {hole_xmax + 0.006, 0.5 * (y_ax + y_acr), zc0, 0.5 * (y_acr - y_ax) * 0.94, 0.5 * (hole_zmax - hole_zmin) * 0.97, 3.2};
    const double x_acr = std::max(half_b, A[kRoot].x + 0.014);
    const double ry_d = 0.5 * (y_acr - y_ax) * 0.9;
    A[kDeltoid] = {0.5 * (A[kRoot].x + x_acr), y_acr - ry_d * 1.02, zc0, ry_d, 0.5 * (hole_zmax - hole_zmin) * 1.08, 2.6};
    A[kAcromion] = {x_acr, y_acr - ry_d, zc0, ry_d, 0.5 * (hole_zmax - hole_zmin) * 1.06, 2.2};
    P.arm_y = y_acr - ry_d * 1.05;
    // Wrist ring first: its thickness fixes where the wrist sits for an exact hand length.
    ArmRing wr{0, P.arm_y, zc0, 0.8, 1.0, 2.2};
    fit_arm_circumference(wr, d.wristc);
    P.dactylion_x = d.span / 2;
    const double x_wr = P.dactylion_x - std::sqrt(std::max(1e-6, d.handl * d.handl - wr.ry * wr.ry));
    P.hand_length = d.handl;
    const double s = (x_wr - x_acr) / (d.ua + d.fa);
    const double x_el = x_acr + s * d.ua;
    auto ring = [&](double x, double c, double ratio) {
      ArmRing r{x, P.arm_y, zc0, 1.0, ratio, 2.2};
      fit_arm_circumference(r, c);
      return r;
    };
    const double biceps = 0.9 * d.bicepsf, forearm = 0.9 * d.forearmf;
    A[kDeltoidLow] = ring(x_acr + 0.3 * s * d.ua, biceps * 1.1, 1.0);
    A[kBiceps] = ring(x_acr + 0.55 * s * d.ua, biceps, 0.95);
    A[kElbow] = ring(x_el, forearm * 0.93, 0.9);
    A[kForearm] = ring(x_el + 0.22 * s * d.fa, forearm, 0.95);
    wr.x = x_wr;
    A[kWrist] = wr;
    const double hl = P.dactylion_x - x_wr;
    const double thick = 0.15 * d.handb + 0.012 * sc;
    A[kPalm] = {x_wr + 0.12 * hl, P.arm_y, zc0, thick * 0.55, d.handb * 0.44, 2.6};
    A[kThumbTop] = {x_wr + 0.32 * hl, P.arm_y, zc0, thick * 0.5, d.handb * 0.49, 2.8};
    // The hand breadth is the straight distance between the knuckle ring's edges, which the
    // knuckle arc (build()) puts at different depths along the hand.
    const double arc_step = knuckle_arc(-1, d.handl) - knuckle_arc(1, d.handl);
    A[kKnuckle] = {x_wr + 0.47 * hl, P.arm_y, zc0, thick * 0.42, 0.5 * std::sqrt(d.handb * d.handb - arc_step * arc_step), 2.8};
    A[kWeb] = {x_wr + 0.54 * hl, P.arm_y, zc0, thick * 0.36, d.handb * 0.48, 3.2};
    for (int key = kKnuckle; key < kArmKeyCount; ++key) A[static_cast<size_t>(key)].flat = 1;  // after the thumb's hole
    std::vector<double> x, yc, zc, ry, rz, pp, fl;
    for (const auto& r : A) {
      x.push_back(r.x); yc.push_back(r.yc); zc.push_back(r.zc); ry.push_back(r.ry); rz.push_back(r.rz); pp.push_back(r.p);
      fl.push_back(r.flat);
    }
    const MonotoneCurve cyc(x, yc), czc(x, zc), cry(x, ry), crz(x, rz), cpp(x, pp), cfl(x, fl);
    P.arm.resize(static_cast<size_t>(arm_ring_count()));
    for (int key = 0; key + 1 < kArmKeyCount; ++key) {
      const int k0 = arm_key_ring(key), n = kArmIntervals[static_cast<size_t>(key)];
      for (int i = 0; i < n; ++i) {
        const double xx = A[key].x + (A[key + 1].x - A[key].x) * i / n;
        ArmRing r{xx, cyc(xx), czc(xx), cry(xx), crz(xx), cpp(xx), std::clamp(cfl(xx), 0.0, 1.0)};
        if (i == 0) r = A[key];
        P.arm[static_cast<size_t>(k0 + i)] = r;
      }
    }
    P.arm[static_cast<size_t>(arm_key_ring(kWeb))] = A[kWeb];
    plan_digits(d, A[kKnuckle], A[kWeb], P);
  }
  return P;
}

// ---- Mesh assembly -----------------------------------------------------------------------
bool in_left_hole(int k, int j, int kax) { return k > kax && k < kax + kHoleRows && j > kHoleJ0 && j < kHoleJ1; }
bool in_hole(int k, int j, int kax) { return in_left_hole(k, j, kax) || in_left_hole(k, (kTorsoN - j) % kTorsoN, kax); }
bool in_thumb_hole(int a, int q, int h0) { return a > h0 && a < h0 + kThumbRows && q > kThumbQ0 && q < kThumbQ1; }
int toe_hole_ring() { return leg_key_ring(kMalleolus) + 1 + kToeRing; }  // the toe holes' upper edge
bool is_toe_column(int k) { return std::find(kToeColumns.begin(), kToeColumns.end(), k) != kToeColumns.end(); }
bool in_toe_hole(int r, int k) { return r == toe_hole_ring() + 1 && is_toe_column(k); }
// The quad between columns k and k + 1 of leg rings r and r + 1 is inside a toe's hole.
bool toe_hole_quad(int r, int k) {
  return (r == toe_hole_ring() || r == toe_hole_ring() + 1) && (is_toe_column(k) || is_toe_column((k + 1) % kLegN));
}

// Grows a digit (DigitPlan) from `base`, a loop of vertices in ring order; appends its rings
// (ring 0 = base) to `rings` and sets `pole`. Side sd: 0 left, 1 right (the left's mirror image).
void grow_digit(Builder& B, int sd, const std::vector<int>& base, const DigitPlan& plan,
                std::vector<std::vector<int>>& rings, int& pole) {
  auto left = [&](int id) { return sd == 0 ? B.v[static_cast<size_t>(id)] : mirror(B.v[static_cast<size_t>(id)]); };
  auto add = [&](const Vec3& p) { return B.add(sd == 0 ? p : mirror(p), plan.part, sd == 0 ? 1 : -1); };
  const int n = static_cast<int>(base.size());
  Vec3 c = Vec3::Zero();
  for (int id : base) c += left(id);
  c /= n;
  Vec3 dir = plan.dir;
  double length = plan.length, root = 0;  // root: from the joint plane to the base, along the axis
  if (plan.tip) {
    dir = (*plan.tip - c).normalized();
    root = plan.root > 0 ? plan.root / dir.x() : 0.0;
    length = (*plan.tip - c).norm() + root;
  } else if (plan.root > 0) {
    root = plan.root / dir.x();
  }
  // A digit grown from the side of the palm (the thumb) leaves it square to its base loop and
  // turns to its direction over the blend, or its first rings would cut into the palm on the side
  // it leans to. Fingers leave the end of the hand, already square to their base.
  Vec3 normal = dir;
  if (!plan.tip && plan.root <= 0) {
    normal = Vec3::Zero();  // Newell's normal of the base loop
    for (int i = 0; i < n; ++i) normal += left(base[static_cast<size_t>(i)]).cross(left(base[static_cast<size_t>((i + 1) % n)]));
    normal.normalize();
    if (normal.dot(dir) < 0) normal = -normal;
  }
  auto frame = [&](const Vec3& d) {  // (side, up) across direction d
    const Vec3 up = (plan.up - plan.up.dot(d) * d).normalized();
    return std::pair<Vec3, Vec3>{d.cross(up), up};
  };
  // The base loop's directions about the axis, and evenly spaced angles in the same order.
  const auto [side0, up0] = frame(normal);
  std::vector<Vec3> offset(static_cast<size_t>(n));
  std::vector<double> theta(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    offset[static_cast<size_t>(i)] = left(base[static_cast<size_t>(i)]) - c;
    const Vec3 e = offset[static_cast<size_t>(i)] - offset[static_cast<size_t>(i)].dot(normal) * normal;
    theta[static_cast<size_t>(i)] = std::atan2(e.dot(up0), e.dot(side0));
  }
  double turn = 0;
  for (int i = 0; i < n; ++i) turn += std::remainder(theta[static_cast<size_t>((i + 1) % n)] - theta[static_cast<size_t>(i)], 2 * kPi);
  const double sense = turn >= 0 ? 1 : -1, step = sense * 2 * kPi / n;
  double sx = 0, sy = 0;
  for (int i = 0; i < n; ++i) sx += std::cos(theta[static_cast<size_t>(i)] - step * i), sy += std::sin(theta[static_cast<size_t>(i)] - step * i);
  const double theta0 = std::atan2(sy, sx);
  // The axis: from the base centre, its direction turning from `normal` to `dir` (integrated in
  // small steps of arc length).
  const double at_base = root / length;
  auto heading = [&](double s) {
    return ((1 - smoothstep(0, plan.blend * length, s)) * normal + smoothstep(0, plan.blend * length, s) * dir).normalized();
  };
  Vec3 centre = c;
  double walked = 0;
  auto walk_to = [&](double s) {
    constexpr int kSteps = 16;
    const double h = (s - walked) / kSteps;
    for (int i = 0; i < kSteps; ++i) centre += h * heading(walked + (i + 0.5) * h);
    walked = s;
  };
  rings.assign(1, base);
  for (size_t k = 0; k < plan.at.size(); ++k) {
    const double along = plan.at[k] * length - root;
    walk_to(along);
    const Vec3 d = heading(along);
    const auto [side, up] = frame(d);
    const double b = smoothstep(at_base, at_base + plan.blend, plan.at[k]);
    std::vector<int> ring;
    for (int i = 0; i < n; ++i) {
      const double a = theta0 + step * i;
      const Vec3 ellipse = side * (plan.half_width[k] * std::cos(a)) + up * (plan.half_thick[k] * std::sin(a));
      const Vec3 own = offset[static_cast<size_t>(i)] - offset[static_cast<size_t>(i)].dot(d) * d;
      ring.push_back(add(centre + (1 - b) * own + b * ellipse));
    }
    rings.push_back(std::move(ring));
  }
  walk_to(length - root);
  pole = add(plan.tip ? *plan.tip : centre);
}

// Emits a digit's faces (strips between its rings, a fan to the pole), outward.
void emit_digit(Builder& B, const std::vector<std::vector<int>>& rings, int pole) {
  const auto& r1 = rings[1];
  const auto& r2 = rings[2];
  Vec3 c = Vec3::Zero();
  for (int id : r1) c += B.v[static_cast<size_t>(id)];
  c /= static_cast<double>(r1.size());
  const Vec3 &a = B.v[static_cast<size_t>(r1[0])], &b = B.v[static_cast<size_t>(r1[1])], &d = B.v[static_cast<size_t>(r2[1])];
  const bool flip = (b - a).cross(d - a).dot(a - c) < 0;
  for (size_t r = 0; r + 1 < rings.size(); ++r) B.strip(rings[r], rings[r + 1], flip);
  B.fan(rings.back(), pole, flip);
}

// Emits triangle t facing `outward`.
void emit_facing(Builder& B, const std::array<int, 3>& t, const Vec3& outward) {
  const Vec3 &a = B.v[static_cast<size_t>(t[0])], &b = B.v[static_cast<size_t>(t[1])], &c = B.v[static_cast<size_t>(t[2])];
  B.tri(t[0], t[1], t[2], (b - a).cross(c - a).dot(outward) < 0);
}

void build(const BodyPlan& P, Builder& B) {
  const int nt = torso_ring_count(), kax = torso_key_ring(kAxilla);
  // Torso, neck, head.
  // A point of ring k at column jf (fractional between columns); the right half (jf > 32) is the
  // exact mirror of the left half.
  auto torso_vertex = [&](int k, double jf) {
    const double jj = jf <= kTorsoN / 2 ? jf : kTorsoN - jf;
    const double t = 2 * kPi * jj / kTorsoN;
    const double s = std::sin(t), c = std::cos(t);
    const double y = torso_point_y(P, k, s, c);
    const auto q = P.torso_resample[static_cast<size_t>(k)] ? torso_xz(P.torso_profile(y), t) : torso_xz(P.torso[static_cast<size_t>(k)], t);
    const double x = (jj == 0 || jj == kTorsoN / 2) ? 0.0 : (jf == jj ? q.x() : -q.x());
    return B.add({x, y, q.y()}, Part::Torso, x == 0 ? 0 : (x > 0 ? 1 : -1));
  };
  B.torso.assign(static_cast<size_t>(nt), std::vector<int>(kTorsoN, -1));
  for (int k = 0; k < nt; ++k)
    for (int j = 0; j < kTorsoN; ++j)
      if (!in_hole(k, j, kax)) B.torso[static_cast<size_t>(k)][static_cast<size_t>(j)] = torso_vertex(k, j);
  // The fine rings' halfway vertices, here on the ring's curve: place_fine() moves them to their
  // chords once the columns are re-spaced (the topology-only builds, for the skin weights and
  // the UVs' ring structure, keep this place, a tenth of a millimetre off).
  B.fine.assign(static_cast<size_t>(fine_last() - fine_first() + 1), std::vector<int>(kTorsoN, -1));
  for (int k = fine_first(); k <= fine_last(); ++k)
    for (int j = 0; j < kTorsoN; ++j)
      if (j < kFineColumns || j >= kTorsoN - kFineColumns)
        B.fine[static_cast<size_t>(k - fine_first())][static_cast<size_t>(j)] = torso_vertex(k, j + 0.5);
  B.head_pole = B.add({0, P.head_top, P.torso.back().cz}, Part::Pole, 0);
  if (B.want_topology) {
    B.island(kIslandTorso);
    for (int k = 0; k + 1 < nt; ++k)
      for (int j = 0; j < kTorsoN; ++j) {
        const int j1 = (j + 1) % kTorsoN;
        const bool hole = (k >= kax && k < kax + kHoleRows) &&
                          ((j >= kHoleJ0 && j < kHoleJ1) || (j >= kTorsoN - kHoleJ1 && j < kTorsoN - kHoleJ0));
        if (hole) continue;
        const int a0 = B.torso_at(k, j), a1 = B.torso_at(k, j1), c0 = B.torso_at(k + 1, j), c1 = B.torso_at(k + 1, j1);
        const int ma = B.fine_at(k, j), mc = B.fine_at(k + 1, j);
        if (ma >= 0 && mc >= 0) {  // two quads, cut along mirror-image diagonals on the two halves
          B.quad(a0, ma, mc, c0, j >= kTorsoN / 2);
          B.quad(ma, a1, c1, mc, j >= kTorsoN / 2);
        } else if (mc >= 0) {  // the fine rings' first: three triangles round the upper edge's middle
          B.tri(a0, a1, mc, false); B.tri(a1, c1, mc, false); B.tri(a0, mc, c0, false);
        } else if (ma >= 0) {  // after their last: round the lower edge's middle
          B.tri(a0, ma, c0, false); B.tri(ma, a1, c1, false); B.tri(ma, c1, c0, false);
        } else {
          B.quad(a0, a1, c1, c0, false);
        }
      }
    B.fan(B.torso.back(), B.head_pole, false);
  }
  // Crotch bridge: along x = 0 from the bottom ring's back centre to its front centre, a
  // half-ellipse dipping to the crotch, so the belly and the buttocks curve under into the
  // crotch instead of ending in a flat shelf.
  const double y_front = B.v[static_cast<size_t>(B.torso[0][0])].y(), y_back = B.v[static_cast<size_t>(B.torso[0][kTorsoN / 2])].y();
  const double z_front = torso_xz(P.torso[0], 0).y(), z_back = torso_xz(P.torso[0], kPi).y();
  B.bridge.clear();
  for (int i = 0; i < kBridge; ++i) {
    const double u = (i + 1.0) / (kBridge + 1.0), c = -std::cos(kPi * u);
    const double y_end = c >= 0 ? y_front : y_back;
    const double y = i == kBridge / 2 ? P.crotch_y : P.crotch_y + (y_end - P.crotch_y) * (1 - std::sin(kPi * u));
    const double z = P.crotch_z + (c >= 0 ? z_front - P.crotch_z : P.crotch_z - z_back) * c;
    B.bridge.push_back(B.add({0, y, z}, Part::Bridge, 0));
  }
  // Legs.
  const int nl = leg_ring_count();
  for (int sd = 0; sd < 2; ++sd) {
    auto& L = B.leg[static_cast<size_t>(sd)];
    L.assign(static_cast<size_t>(nl), std::vector<int>(kLegN, -1));
    for (int k = 0; k <= 32; ++k) L[0][static_cast<size_t>(k)] = B.torso[0][static_cast<size_t>(sd == 0 ? k : (kTorsoN - k) % kTorsoN)];
    for (int k = 33; k < kLegN; ++k) L[0][static_cast<size_t>(k)] = B.bridge[static_cast<size_t>(k - 33)];
    for (int r = 1; r < nl; ++r) {
      const LegRing& g = P.leg[static_cast<size_t>(r)];
      const auto phi = foot_angles(g);
      for (int k = 0; k < kLegN; ++k) {
        if (in_toe_hole(r, k)) continue;
        const auto q = leg_xz(g, phi[static_cast<size_t>(k)]);
        double y = g.y;
        if (r == 1) {  // under a dropped seat: follow the torso column above (k ≤ 32) or the bridge
          double s = 0, c = -1;
          if (k <= kTorsoN / 2) { s = std::sin(2 * kPi * k / kTorsoN); c = std::cos(2 * kPi * k / kTorsoN); }
          else c = -std::cos(kPi * (k - kTorsoN / 2) / (kBridge + 1.0));
          y += P.seat_drop_side * s * s + P.seat_drop_back * std::max(0.0, -c) * std::max(0.0, -c);
        }
        Vec3 p{q.x(), y, q.y()};
        // The crotch: the legs' first rings stand kCrotchOpen further from the mid-line on their
        // medial side, so the surface rounds under the crotch bridge instead of folding there
        // (the two thighs' faces met at the bridge about 40° apart, the torso's largest crease).
        if (r == 1) p.x() += kCrotchOpen * (P.head_top / 1.70) * smoothstep(0.3, 1.0, -std::sin(phi[static_cast<size_t>(k)]));
        L[static_cast<size_t>(r)][static_cast<size_t>(k)] = B.add(sd == 0 ? p : mirror(p), Part::Leg, sd == 0 ? 1 : -1);
      }
    }
    // Toes: grown from the loops around their holes in the forefoot's front.
    const int th = toe_hole_ring();
    for (int t = 0; t < kToeCount; ++t) {
      const int c = kToeColumns[static_cast<size_t>(t)];
      auto at = [&](int r, int k) { return L[static_cast<size_t>(r)][static_cast<size_t>((k + kLegN) % kLegN)]; };
      const std::vector<int> loop = {at(th, c - 1),     at(th, c),         at(th, c + 1),     at(th + 1, c + 1),
                                     at(th + 2, c + 1), at(th + 2, c),     at(th + 2, c - 1), at(th + 1, c - 1)};
      grow_digit(B, sd, loop, P.toe[static_cast<size_t>(t)], B.toe[static_cast<size_t>(sd)][static_cast<size_t>(t)],
                 B.toe_pole[static_cast<size_t>(sd)][static_cast<size_t>(t)]);
    }
    if (B.want_topology) {
      B.island(kIslandLeg + sd);
      for (int r = 0; r + 1 < nl; ++r)
        B.strip(L[static_cast<size_t>(r)], L[static_cast<size_t>(r + 1)], sd == 0,
                [r](size_t k) { return toe_hole_quad(r, static_cast<int>(k)); });
      B.island(kIslandSole + sd);
      // Sole: zip the lateral and medial halves of the last ring from toe to heel.
      const auto& R = L.back();
      std::vector<int> lat, med;
      for (int k = kLegFront; k <= kLegBack; ++k) lat.push_back(R[static_cast<size_t>(k)]);
      for (int k = kLegFront; k != kLegBack; k = (k + kLegN - 1) % kLegN) med.push_back(R[static_cast<size_t>(k)]);
      med.push_back(R[kLegBack]);
      // Both halves run toe → heel and share those two ends.
      const int toe = lat.front(), heel = lat.back();
      auto emit = [&](int a, int b, int c) {
        const Vec3 &pa = B.v[static_cast<size_t>(a)], &pb = B.v[static_cast<size_t>(b)], &pc = B.v[static_cast<size_t>(c)];
        const double ny = (pb - pa).cross(pc - pa).y();
        B.tri(a, b, c, ny > 0);  // the sole faces down
      };
      int prev_l = lat[1], prev_m = med[1];
      emit(toe, prev_l, prev_m);
      size_t i = 2, j = 2;
      const size_t nl_ = lat.size() - 1, nm_ = med.size() - 1;  // exclude the heel
      while (i < nl_ || j < nm_) {
        const bool take_lat = j >= nm_ ||
                              (i < nl_ && B.v[static_cast<size_t>(lat[i])].z() >= B.v[static_cast<size_t>(med[j])].z());
        if (take_lat) { emit(prev_l, prev_m, lat[i]); prev_l = lat[i]; ++i; }
        else { emit(prev_l, prev_m, med[j]); prev_m = med[j]; ++j; }
      }
      emit(prev_l, prev_m, heel);
      for (int t = 0; t < kToeCount; ++t) {
        B.island(kIslandToe + kToeCount * sd + t);
        emit_digit(B, B.toe[static_cast<size_t>(sd)][static_cast<size_t>(t)], B.toe_pole[static_cast<size_t>(sd)][static_cast<size_t>(t)]);
      }
    }
  }
  // Arms, hands, thumbs.
  const int na = arm_ring_count(), h0 = arm_key_ring(kPalm);
  for (int sd = 0; sd < 2; ++sd) {
    auto& A = B.arm[static_cast<size_t>(sd)];
    A.assign(static_cast<size_t>(na), std::vector<int>(kArmN, -1));
    auto tj = [&](int j) { return sd == 0 ? j : (kTorsoN - j) % kTorsoN; };
    int q = 0;
    for (int j = kHoleJ0; j < kHoleJ1; ++j) A[0][static_cast<size_t>(q++)] = B.torso[static_cast<size_t>(kax)][static_cast<size_t>(tj(j))];
    for (int k = kax; k < kax + kHoleRows; ++k) A[0][static_cast<size_t>(q++)] = B.torso[static_cast<size_t>(k)][static_cast<size_t>(tj(kHoleJ1))];
    for (int j = kHoleJ1; j > kHoleJ0; --j) A[0][static_cast<size_t>(q++)] = B.torso[static_cast<size_t>(kax + kHoleRows)][static_cast<size_t>(tj(j))];
    for (int k = kax + kHoleRows; k > kax; --k) A[0][static_cast<size_t>(q++)] = B.torso[static_cast<size_t>(k)][static_cast<size_t>(tj(kHoleJ0))];
    const int r_thumb_top = arm_key_ring(kThumbTop), r_knuckle = arm_key_ring(kKnuckle);
    for (int r = 1; r < na; ++r) {
      const ArmRing& ring = P.arm[static_cast<size_t>(r)];
      const std::array<double, kArmN> psi = arm_column_angles(ring);
      // The knuckle arc (knuckle_arc()) fades in from the thumb's top to the knuckles.
      const double arc = smoothstep(r_thumb_top, r_knuckle, r);
      for (int qq = 0; qq < kArmN; ++qq) {
        if (in_thumb_hole(r, qq, h0)) continue;
        Vec3 p = arm_point(ring, psi[static_cast<size_t>(qq)]);
        const double across = (p.z() - ring.zc) / ring.rz;
        if (arc > 0) p.x() -= arc * knuckle_arc(across, P.hand_length);
        p.y() += knuckle_bumps(ring, P.arm[static_cast<size_t>(r_knuckle)].x, across, p.y(), P.hand_length);
        A[static_cast<size_t>(r)][static_cast<size_t>(qq)] = B.add(sd == 0 ? p : mirror(p), Part::Arm, sd == 0 ? 1 : -1);
      }
    }
    // Thumb: grown from the loop around its hole in the palm.
    std::vector<int> loop;
    for (int qq = kThumbQ0; qq < kThumbQ1; ++qq) loop.push_back(A[static_cast<size_t>(h0)][static_cast<size_t>(qq)]);
    for (int a = h0; a < h0 + kThumbRows; ++a) loop.push_back(A[static_cast<size_t>(a)][kThumbQ1]);
    for (int qq = kThumbQ1; qq > kThumbQ0; --qq) loop.push_back(A[static_cast<size_t>(h0 + kThumbRows)][static_cast<size_t>(qq)]);
    for (int a = h0 + kThumbRows; a > h0; --a) loop.push_back(A[static_cast<size_t>(a)][kThumbQ0]);
    grow_digit(B, sd, loop, P.thumb, B.thumb[static_cast<size_t>(sd)], B.thumb_pole[static_cast<size_t>(sd)]);
    // Fingers: grown from their arcs of the web ring.
    const auto& web = A[static_cast<size_t>(na - 1)];
    for (int f = 0; f < kFingerCount; ++f) {
      std::vector<int> base;
      for (int qq : kFingerColumns[static_cast<size_t>(f)]) base.push_back(web[static_cast<size_t>(qq)]);
      grow_digit(B, sd, base, P.finger[static_cast<size_t>(f)], B.finger[static_cast<size_t>(sd)][static_cast<size_t>(f)],
                 B.finger_pole[static_cast<size_t>(sd)][static_cast<size_t>(f)]);
    }
    if (B.want_topology) {
      const bool flip = sd == 1;
      B.island(kIslandArm + sd);
      for (int r = 0; r + 1 < na; ++r)
        for (int qq = 0; qq < kArmN; ++qq) {
          if (r >= h0 && r < h0 + kThumbRows && qq >= kThumbQ0 && qq < kThumbQ1) continue;
          const int q1 = (qq + 1) % kArmN;
          const auto& R0 = A[static_cast<size_t>(r)];
          const auto& R1 = A[static_cast<size_t>(r + 1)];
          B.tri(R0[static_cast<size_t>(qq)], R0[static_cast<size_t>(q1)], R1[static_cast<size_t>(q1)], flip);
          B.tri(R0[static_cast<size_t>(qq)], R1[static_cast<size_t>(q1)], R1[static_cast<size_t>(qq)], flip);
        }
      B.island(kIslandThumb + sd);
      emit_digit(B, B.thumb[static_cast<size_t>(sd)], B.thumb_pole[static_cast<size_t>(sd)]);
      for (int f = 0; f < kFingerCount; ++f) {
        B.island(kIslandFinger + kFingerCount * sd + f);
        emit_digit(B, B.finger[static_cast<size_t>(sd)][static_cast<size_t>(f)], B.finger_pole[static_cast<size_t>(sd)][static_cast<size_t>(f)]);
      }
      // The webs: one quad between each two neighbouring fingers' arcs, facing the fingertips.
      B.island(kIslandWeb + sd);
      for (const auto& quad : kWebQuads) {
        auto at = [&](int i) { return web[static_cast<size_t>(quad[static_cast<size_t>(i)])]; };
        emit_facing(B, {at(0), at(1), at(2)}, Vec3(sd == 0 ? 1 : -1, 0, 0));
        emit_facing(B, {at(0), at(2), at(3)}, Vec3(sd == 0 ? 1 : -1, 0, 0));
      }
    }
  }
}

void add_landmarks(Builder& B) {
  auto& L = B.landmarks;
  auto T = [&](int key, int j) { return B.torso[static_cast<size_t>(torso_key_ring(key))][static_cast<size_t>(j)]; };
  const int mirror_j = kTorsoN;
  L["vertex"] = B.head_pole;
  L["cervicale"] = T(kCervicale, 32);
  L["suprasternale"] = T(kHoleTop, 0);
  L["chest_front"] = T(kChest, 0);
  L["omphalion"] = T(kWaist, 0);
  L["buttock_back"] = T(kHip, 32);
  L["gluteal_furrow"] = T(kLow, 32);
  L["crotch"] = B.bridge[kBridge / 2];
  L["neck_front"] = T(kNeck, 0);
  L["glabella"] = T(kGlabella, 0);
  L["head_circumference_front"] = T(kGlabella, 0);
  L["opisthocranion"] = T(kGlabella, 32);
  const int jt = static_cast<int>(std::lround(0.72 / (2 * kPi) * kTorsoN));
  for (int sd = 0; sd < 2; ++sd) {
    const std::string s = sd == 0 ? "_left" : "_right";
    auto J = [&](int j) { return sd == 0 ? j : (mirror_j - j) % kTorsoN; };
    L["acromion" + s] = B.arm[static_cast<size_t>(sd)][static_cast<size_t>(arm_key_ring(kAcromion))][kArmTop];
    L["axilla" + s] = T(kArmpit, J(16));
    L["thelion" + s] = T(kChest, J(jt));
    L["iliocristale" + s] = T(kIlio, J(16));
    L["trochanterion" + s] = T(kLow, J(16));
    L["hip" + s] = T(kHip, J(16));
    L["head_side" + s] = T(kGlabella, J(16));
    const auto& G = B.leg[static_cast<size_t>(sd)];
    auto leg = [&](int ring, int k) { return G[static_cast<size_t>(ring)][static_cast<size_t>(k)]; };
    const int fb = leg_key_ring(kMalleolus) + 1 + kFootBreadthRing, fh = leg_key_ring(kMalleolus) + 1 + kHeelRing;
    L["thigh" + s] = leg(leg_key_ring(kThigh), kLegLateral);
    L["lower_thigh" + s] = leg(leg_key_ring(kLowerThigh), kLegLateral);
    L["knee" + s] = leg(leg_key_ring(kKnee), kLegFront);
    L["calf" + s] = leg(leg_key_ring(kCalf), kLegBack);
    L["ankle" + s] = leg(leg_key_ring(kAnkle), kLegLateral);
    L["lateral_malleolus" + s] = leg(leg_key_ring(kMalleolus), kLegLateral);
    L["heel" + s] = leg(fh, kLegBack);
    L["toe" + s] = B.toe_pole[static_cast<size_t>(sd)][0];
    L["foot_lateral" + s] = leg(fb, kLegLateral);
    L["foot_medial" + s] = leg(fb, kLegMedial);
    const auto& A = B.arm[static_cast<size_t>(sd)];
    auto arm = [&](int key, int q) { return A[static_cast<size_t>(arm_key_ring(key))][static_cast<size_t>(q)]; };
    L["radiale" + s] = arm(kElbow, kArmFront);
    L["stylion" + s] = arm(kWrist, kArmFront);
    L["ulnar_styloid" + s] = arm(kWrist, kArmBack);
    L["biceps" + s] = arm(kBiceps, kArmTop);
    L["forearm" + s] = arm(kForearm, kArmTop);
    L["wrist" + s] = arm(kWrist, kArmBottom);
    L["dactylion" + s] = B.finger_pole[static_cast<size_t>(sd)][kMiddle];
    L["metacarpal" + s] = arm(kKnuckle, kArmFront);
    L["metacarpal_ulnar" + s] = arm(kKnuckle, kArmBack);
  }
}

}  // namespace
}  // namespace caliper::mannequin

namespace caliper::mannequin {
namespace {

// ---- Rig: joint regressor and skinning weights (from the typical neutral body) -------------
enum J {
  Pelvis, LHip, RHip, Spine1, LKnee, RKnee, Spine2, LAnkle, RAnkle, Spine3, LFoot, RFoot, Neck, LCollar, RCollar,
  Head, LShoulder, RShoulder, LElbow, RElbow, LWrist, RWrist, LHand, RHand, FirstFingerJoint,
  JointCount = FirstFingerJoint + 30
};
// Joint k (0: knuckle … 2: last) of finger f (Finger, or kFingerCount for the thumb) on side sd,
// in rig_joint_names()'s SMPL-H order (index, middle, pinky, ring, thumb).
int digit_joint(int sd, int f, int k) {
  constexpr std::array<int, kFingerCount + 1> kSmplhOrder = {0, 1, 3, 2, 4};  // by Finger, then the thumb
  return FirstFingerJoint + 15 * sd + 3 * kSmplhOrder[static_cast<size_t>(f)] + k;
}

using Weights = std::vector<std::pair<int, double>>;  // (vertex or joint, weight)

Vec3 combo(const Builder& B, const Weights& w) {
  Vec3 p = Vec3::Zero();
  for (auto [i, a] : w) p += a * B.v[static_cast<size_t>(i)];
  return p;
}
void add_mean(Weights& out, const std::vector<int>& ids, double total) {
  std::vector<int> valid;
  for (int i : ids) if (i >= 0) valid.push_back(i);
  for (int i : valid) out.push_back({i, total / static_cast<double>(valid.size())});
}

// The shoulder's weights, diffused over the surface around it. The chains give the arm to the
// shoulder joint by its distance out along the arm and the torso to the collar by height and
// distance from the midline, so around the armpit the weights change within a couple of
// centimetres: the arm lowered into an A-pose folds the skin there into a crease, and raised 60°
// above the horizontal the typical man's armpit folds flat and through itself. Averaging each
// vertex's weights with its neighbours' (kShoulderSmoothRounds rounds, fading out towards the
// zone's edge), as a rigger's weight smoothing does, lets the arm's root follow the collar and
// the torso a little. Only vertices out from about the shoulder joint change (fading in over the
// 3 cm inside it), so the torso's own vertices keep the joint that moves them most (the crease
// measure's regions); the rows still sum to 1.
void smooth_shoulder_weights(const Builder& B, const std::array<Vec3, JointCount>& joint, double sc,
                             std::vector<Weights>& vw) {
  const std::vector<std::set<int>> nb = one_rings(B);
  std::vector<double> zone(B.v.size(), 0.0);
  const Vec3& sh = joint[LShoulder];
  for (size_t i = 0; i < B.v.size(); ++i) {
    if (B.part[i] != Part::Torso && B.part[i] != Part::Arm) continue;
    const Vec3 p(std::abs(B.v[i].x()), B.v[i].y(), B.v[i].z());
    const double d = (p - sh).norm();
    zone[i] = (1 - smoothstep(kShoulderSmoothInner * sc, kShoulderSmoothOuter * sc, d)) *
              smoothstep(sh.x() - 0.04 * sc, sh.x() - 0.01 * sc, p.x());
  }
  for (int round = 0; round < kShoulderSmoothRounds; ++round) {
    std::vector<Weights> next = vw;
    for (size_t i = 0; i < vw.size(); ++i) {
      if (zone[i] <= 0) continue;
      std::map<int, double> mean;
      for (int n : nb[i]) for (auto [j, a] : vw[static_cast<size_t>(n)]) mean[j] += a / static_cast<double>(nb[i].size());
      std::map<int, double> mixed;
      for (auto [j, a] : vw[i]) mixed[j] += (1 - 0.5 * zone[i]) * a;
      for (auto [j, a] : mean) mixed[j] += 0.5 * zone[i] * a;
      next[i].assign(mixed.begin(), mixed.end());
    }
    vw = std::move(next);
  }
}

Topology make_topology() {
  const Dimensions dims = typical_dimensions(Sex::Neutral);
  Builder B;
  B.want_topology = true;
  build(plan_body(to_dims(dims), Sex::Neutral), B);
  add_landmarks(B);
  Topology topo;
  topo.vertex_count = static_cast<int>(B.v.size());
  topo.faces.resize(static_cast<Eigen::Index>(B.faces.size()), 3);
  for (size_t f = 0; f < B.faces.size(); ++f)
    for (int c = 0; c < 3; ++c) topo.faces(static_cast<Eigen::Index>(f), c) = B.faces[f][static_cast<size_t>(c)];
  topo.landmarks = B.landmarks;

  // Joint regressor: each joint a convex combination of ring vertices (so joints follow shape).
  std::array<Weights, JointCount> jr;
  auto torso_ring = [&](int k) { return B.torso[static_cast<size_t>(k)]; };
  {
    add_mean(jr[Pelvis], torso_ring(0), 0.7);
    add_mean(jr[Pelvis], torso_ring(torso_key_ring(kHip)), 0.3);
    const int k1 = torso_key_ring(kHip) + 3, k2 = torso_key_ring(kUnderBust), k3 = torso_key_ring(kChest) + 1;
    const std::array<std::pair<J, int>, 3> sp = {{{Spine1, k1}, {Spine2, k2}, {Spine3, k3}}};
    for (auto [j, k] : sp) {
      add_mean(jr[j], torso_ring(k), 0.65);
      jr[j].push_back({B.torso[static_cast<size_t>(k)][32], 0.35});
    }
    add_mean(jr[Neck], torso_ring(torso_key_ring(kNeck)), 1.0);
    add_mean(jr[Head], torso_ring(torso_key_ring(kChin)), 0.5);
    add_mean(jr[Head], torso_ring(torso_key_ring(kMouth)), 0.5);
  }
  for (int sd = 0; sd < 2; ++sd) {
    const auto& L = B.leg[static_cast<size_t>(sd)];
    const auto& A = B.arm[static_cast<size_t>(sd)];
    const int hip = sd == 0 ? LHip : RHip, knee = sd == 0 ? LKnee : RKnee, ankle = sd == 0 ? LAnkle : RAnkle,
              foot = sd == 0 ? LFoot : RFoot, collar = sd == 0 ? LCollar : RCollar,
              shoulder = sd == 0 ? LShoulder : RShoulder, elbow = sd == 0 ? LElbow : RElbow,
              wrist = sd == 0 ? LWrist : RWrist, hand = sd == 0 ? LHand : RHand;
    auto tj = [&](int j) { return sd == 0 ? j : (kTorsoN - j) % kTorsoN; };
    add_mean(jr[static_cast<size_t>(hip)], L[1], 0.5);
    const int kh = torso_key_ring(kHip);
    add_mean(jr[static_cast<size_t>(hip)], {B.torso[static_cast<size_t>(kh)][0], B.torso[static_cast<size_t>(kh)][32],
                                            B.torso[static_cast<size_t>(kh)][static_cast<size_t>(tj(16))]}, 0.5);
    add_mean(jr[static_cast<size_t>(knee)], L[static_cast<size_t>(leg_key_ring(kKnee))], 1.0);
    add_mean(jr[static_cast<size_t>(ankle)], L[static_cast<size_t>(leg_key_ring(kMalleolus))], 1.0);
    const int fr = leg_key_ring(kMalleolus) + 1 + kFootBreadthRing - 2;
    add_mean(jr[static_cast<size_t>(foot)], {L[static_cast<size_t>(fr)][kLegLateral], L[static_cast<size_t>(fr)][kLegMedial]}, 1.0);
    std::vector<int> half;
    for (int j = 0; j <= 32; ++j) half.push_back(B.torso[static_cast<size_t>(torso_key_ring(kShoulder1))][static_cast<size_t>(tj(j))]);
    add_mean(jr[static_cast<size_t>(collar)], half, 1.0);
    add_mean(jr[static_cast<size_t>(shoulder)], A[static_cast<size_t>(arm_key_ring(kDeltoid))], 1.0);
    add_mean(jr[static_cast<size_t>(elbow)], A[static_cast<size_t>(arm_key_ring(kElbow))], 1.0);
    add_mean(jr[static_cast<size_t>(wrist)], A[static_cast<size_t>(arm_key_ring(kWrist))], 1.0);
    const auto& knuckles = A[static_cast<size_t>(arm_key_ring(kKnuckle))];
    add_mean(jr[static_cast<size_t>(hand)], knuckles, 1.0);
    // Fingers: the knuckle joint under the finger's columns of the knuckle ring, the other two at
    // their rings. The thumb's first joint sits inside the palm, between its base and the palm's middle.
    for (int f = 0; f < kFingerCount; ++f) {
      std::vector<int> under;
      for (int q : kFingerColumns[static_cast<size_t>(f)]) under.push_back(knuckles[static_cast<size_t>(q)]);
      const auto& F = B.finger[static_cast<size_t>(sd)][static_cast<size_t>(f)];
      add_mean(jr[static_cast<size_t>(digit_joint(sd, f, 0))], under, 1.0);
      add_mean(jr[static_cast<size_t>(digit_joint(sd, f, 1))], F[kPipRing + 1], 1.0);
      add_mean(jr[static_cast<size_t>(digit_joint(sd, f, 2))], F[kDipRing + 1], 1.0);
    }
    const auto& T = B.thumb[static_cast<size_t>(sd)];
    add_mean(jr[static_cast<size_t>(digit_joint(sd, kFingerCount, 0))], T[0], 0.6);
    add_mean(jr[static_cast<size_t>(digit_joint(sd, kFingerCount, 0))], A[static_cast<size_t>(arm_key_ring(kPalm) + 1)], 0.4);
    add_mean(jr[static_cast<size_t>(digit_joint(sd, kFingerCount, 1))], T[kThumbMcpRing + 1], 1.0);
    add_mean(jr[static_cast<size_t>(digit_joint(sd, kFingerCount, 2))], T[kThumbIpRing + 1], 1.0);
  }
  std::vector<Eigen::Triplet<double>> trip;
  std::array<Vec3, JointCount> joint{};
  for (int j = 0; j < JointCount; ++j) {
    for (auto [i, w] : jr[static_cast<size_t>(j)]) trip.emplace_back(j, i, w);
    joint[static_cast<size_t>(j)] = combo(B, jr[static_cast<size_t>(j)]);
  }
  topo.joint_regressor.resize(JointCount, topo.vertex_count);
  topo.joint_regressor.setFromTriplets(trip.begin(), trip.end());

  // Skinning: each vertex on a chain of joints (a 1-D coordinate along its limb); owned by the
  // segment it lies on, blended with smoothstep across a band around each joint.
  struct Chain { std::vector<int> joints; std::vector<double> at, band; };
  auto chain_weights = [](const Chain& c, double x, Weights& out) {
    // c.at increasing; segment i (between at[i] and at[i+1]) belongs to joints[i]; before at[0] to
    // joints[0] as well (the chain's parent is joints[0]).
    size_t seg = 0;
    while (seg + 1 < c.at.size() && x >= c.at[seg + 1]) ++seg;
    for (size_t b = 1; b < c.at.size(); ++b) {
      if (std::abs(x - c.at[b]) < c.band[b]) {
        const double t = smoothstep(c.at[b] - c.band[b], c.at[b] + c.band[b], x);
        out.push_back({c.joints[b - 1], 1 - t});
        out.push_back({c.joints[b], t});
        return;
      }
    }
    out.push_back({c.joints[seg], 1.0});
  };
  const double sc = joint[Head].y() / 1.55;
  // Which finger's knuckle each hand vertex follows: the finger above its column of the hand's
  // rings (the palm from the wrist on), or the finger it belongs to.
  struct Digit { int finger = -1; };
  std::vector<Digit> digit(B.v.size());
  for (int sd = 0; sd < 2; ++sd) {
    const auto& A = B.arm[static_cast<size_t>(sd)];
    for (int f = 0; f < kFingerCount; ++f) {
      for (int q : kFingerColumns[static_cast<size_t>(f)])
        for (int r = arm_key_ring(kWrist); r < arm_ring_count(); ++r)
          if (const int id = A[static_cast<size_t>(r)][static_cast<size_t>(q)]; id >= 0) digit[static_cast<size_t>(id)].finger = f;
      for (const auto& ring : B.finger[static_cast<size_t>(sd)][static_cast<size_t>(f)])
        for (int id : ring) digit[static_cast<size_t>(id)].finger = f;
      digit[static_cast<size_t>(B.finger_pole[static_cast<size_t>(sd)][static_cast<size_t>(f)])].finger = f;
    }
  }
  std::vector<Weights> vw(B.v.size());
  for (size_t i = 0; i < B.v.size(); ++i) {
    const Vec3& p = B.v[i];
    const bool left = p.x() >= 0;
    Weights& w = vw[i];
    const Part part = B.part[i];
    const double ax = std::abs(p.x());
    const int hip = left ? LHip : RHip, knee = left ? LKnee : RKnee, ankle = left ? LAnkle : RAnkle,
              foot = left ? LFoot : RFoot, collar = left ? LCollar : RCollar, shoulder = left ? LShoulder : RShoulder,
              elbow = left ? LElbow : RElbow, wrist = left ? LWrist : RWrist, hand = left ? LHand : RHand;
    if (part == Part::Leg || (part == Part::Bridge)) {
      if (part == Part::Bridge) { w.push_back({Pelvis, 0.5}); w.push_back({LHip, 0.25}); w.push_back({RHip, 0.25}); continue; }
      // Coordinate: depth below the hip joint (increasing downwards).
      const double depth = -p.y();
      Chain c{{Pelvis, hip, knee, ankle}, {-1e9, -joint[static_cast<size_t>(hip)].y(), -joint[static_cast<size_t>(knee)].y(), -joint[static_cast<size_t>(ankle)].y()},
              {0, 0.07 * sc, 0.05 * sc, 0.03 * sc}};
      Weights base;
      chain_weights(c, depth, base);
      // Toes bend about the ball of the foot.
      const double zf = joint[static_cast<size_t>(foot)].z();
      const double toe = p.y() < joint[static_cast<size_t>(ankle)].y() ? smoothstep(zf - 0.02 * sc, zf + 0.02 * sc, p.z()) : 0.0;
      for (auto [j, a] : base) {
        if (j == ankle && toe > 0) { w.push_back({ankle, a * (1 - toe)}); w.push_back({foot, a * toe}); }
        else w.push_back({j, a});
      }
      continue;
    }
    if (part == Part::Arm || part == Part::Thumb || part == Part::Finger) {
      const Digit dg = digit[i];
      if (part == Part::Thumb) {  // along the thumb from the wrist through its three joints
        const int sd = left ? 0 : 1;
        const Vec3& t1 = joint[static_cast<size_t>(digit_joint(sd, kFingerCount, 0))];
        const Vec3 axis = (joint[static_cast<size_t>(digit_joint(sd, kFingerCount, 2))] - t1).normalized();
        auto along = [&](int k) { return (joint[static_cast<size_t>(digit_joint(sd, kFingerCount, k))] - t1).dot(axis); };
        Chain c{{wrist, digit_joint(sd, kFingerCount, 0), digit_joint(sd, kFingerCount, 1), digit_joint(sd, kFingerCount, 2)},
                {-1e9, 0.0, along(1), along(2)},
                {0, 0.012 * sc, 0.01 * sc, 0.008 * sc}};
        chain_weights(c, (p - t1).dot(axis), w);
        continue;
      }
      // Arm and palm along the arm; the hand's last stretch (the knuckles onwards) belongs to the
      // knuckle joint of the finger above it, then along the finger to its other two joints.
      const int sd = left ? 0 : 1;
      const int f = dg.finger;
      const int knuckle = f >= 0 ? digit_joint(sd, f, 0) : hand;
      Chain c{{collar, shoulder, elbow, wrist, knuckle},
              {-1e9, std::abs(joint[static_cast<size_t>(shoulder)].x()), std::abs(joint[static_cast<size_t>(elbow)].x()),
               std::abs(joint[static_cast<size_t>(wrist)].x()), std::abs(joint[static_cast<size_t>(hand)].x())},
              {0, 0.04 * sc, 0.05 * sc, 0.025 * sc, 0.015 * sc}};
      Weights arm;
      chain_weights(c, ax, arm);
      if (part != Part::Finger) { w = arm; continue; }
      const Vec3& k1 = joint[static_cast<size_t>(knuckle)];
      const Vec3 axis = (joint[static_cast<size_t>(digit_joint(sd, f, 2))] - k1).normalized();
      auto along = [&](int k) { return (joint[static_cast<size_t>(digit_joint(sd, f, k))] - k1).dot(axis); };
      Chain fc{{knuckle, digit_joint(sd, f, 1), digit_joint(sd, f, 2)}, {-1e9, along(1), along(2)}, {0, 0.01 * sc, 0.008 * sc}};
      Weights finger;
      chain_weights(fc, (p - k1).dot(axis), finger);
      for (auto [j, a] : arm) {
        if (j != knuckle) { w.push_back({j, a}); continue; }
        for (auto [jf, af] : finger) w.push_back({jf, a * af});
      }
      continue;
    }
    // Torso, neck and head.
    {
      Chain c{{Pelvis, Spine1, Spine2, Spine3, Neck, Head},
              {-1e9, joint[Spine1].y(), joint[Spine2].y(), joint[Spine3].y(), joint[Neck].y(), joint[Head].y()},
              {0, 0.04 * sc, 0.05 * sc, 0.05 * sc, 0.03 * sc, 0.03 * sc}};
      Weights base;
      chain_weights(c, p.y(), base);
      // Thighs' tops follow the hips; the shoulders' tops and armpits follow the collars.
      const double hip_w = (1 - smoothstep(joint[LHip].y() - 0.02 * sc, joint[LHip].y() + 0.08 * sc, p.y())) *
                           smoothstep(0.02 * sc, 0.1 * sc, ax) * 0.6;
      const double col_w = smoothstep(joint[LCollar].y() - 0.2 * sc, joint[LCollar].y() - 0.02 * sc, p.y()) *
                           (1 - smoothstep(joint[Neck].y() - 0.01 * sc, joint[Neck].y() + 0.03 * sc, p.y())) *
                           smoothstep(0.05 * sc, 0.14 * sc, ax);
      for (auto [j, a] : base) w.push_back({j, a * (1 - hip_w) * (1 - col_w)});
      if (hip_w > 0) w.push_back({hip, hip_w * (1 - col_w)});
      if (col_w > 0) w.push_back({ax > std::abs(joint[static_cast<size_t>(shoulder)].x()) - 0.02 ? shoulder : collar, col_w});
    }
  }
  smooth_shoulder_weights(B, joint, sc, vw);
  trip.clear();
  for (size_t i = 0; i < vw.size(); ++i) {
    std::map<int, double> merged;
    for (auto [j, a] : vw[i]) if (a > 1e-9) merged[j] += a;
    std::vector<std::pair<double, int>> sorted;
    for (auto [j, a] : merged) sorted.push_back({a, j});
    std::sort(sorted.begin(), sorted.end(), [](auto& x, auto& y) { return x.first > y.first || (x.first == y.first && x.second < y.second); });
    if (sorted.size() > 4) sorted.resize(4);
    double total = 0;
    for (auto& s : sorted) total += s.first;
    for (auto& s : sorted) trip.emplace_back(static_cast<int>(i), s.second, s.first / total);
  }
  topo.skin_weights.resize(topo.vertex_count, JointCount);
  topo.skin_weights.setFromTriplets(trip.begin(), trip.end());
  return topo;
}

}  // namespace

const std::vector<std::string>& input_columns() { return kColumns; }

Dimensions typical_dimensions(Sex sex) {
  Dimensions d;
  for (size_t i = 0; i < kColumns.size(); ++i) {
    const double f = kFemaleMeans[i] / 1000, m = kMaleMeans[i] / 1000;
    d[kColumns[i]] = sex == Sex::Female ? f : sex == Sex::Male ? m : 0.5 * (f + m);
  }
  return d;
}

Dimensions complete_dimensions(const Dimensions& partial, Sex sex) {
  const Dimensions typical = typical_dimensions(sex);
  double scale = 1;
  if (auto it = partial.find("stature"); it != partial.end() && std::isfinite(it->second) && it->second > 0)
    scale = it->second / typical.at("stature");
  Dimensions out = partial;
  for (const auto& [k, v] : typical)
    if (!out.count(k)) out[k] = v * scale;
  return out;
}

// ---- Fairing the arm's junction with the torso --------------------------------------------
// The arm tube leaves the torso through a hole in its side at nearly a right angle: a seam all
// round the shoulder (the "doll joint"; `caliper model creases` measures ~120° on the mean body)
// and a square shoulder top. Taubin's λ|μ smoothing (Taubin 1995, "A signal processing approach
// to fair surface design") of the vertices around the hole turns the seam into a fillet without
// shrinking the body. Only vertices that carry no landmark and lie on no imposed section move, so
// every fidelity target is kept. The left side is smoothed and mirrored, so bodies stay exactly
// symmetric.
//
// The fillet still turns inward where the arm's underside meets the torso's side in front of and
// behind the armpit: a notch in every three-quarter view, which the arm lowered into the A-pose
// folds into a crease. A real armpit is closed there by two webs, the anterior fold (pectoralis
// major's border) and the posterior fold (latissimus dorsi, teres major). After the smoothing,
// the same shoulder vertices are moved by mean curvature flow run one way (fair()'s second pass): a
// concave vertex moves outward along its normal by the normal part of the umbrella operator, a
// convex one stays, so valleys fill and ridges keep their shape.
struct Fairing {
  std::vector<int> left, right;              // free vertices; right[i] mirrors left[i]
  std::vector<Vec3> freedom;                 // per axis, 1 where left[i] may move, 0 where not
  std::vector<double> weight;                // share of each smoothing step taken
  std::vector<char> hole_bottom;             // 1: on the armpit hole's bottom edge (see fair())
  std::vector<double> fill;                  // share of each fold-filling step taken (0: none)
  std::vector<std::vector<int>> neighbours;  // one-ring of left[i]
  std::vector<std::vector<std::array<int, 3>>> faces;  // the faces round left[i], outward
};
constexpr int kFoldFillIterations = 40, kFoldFillFade = 6;
constexpr int kFairChinRingsAbove = 2, kFairChinColumns = 14;  // the jaw's fairing (make_fairing())
// No faired vertex may have a halfway vertex of the fine rings in its one-ring: the fine rings'
// first transition triangles reach down one ring under them.
static_assert(kFineAboveChin >= kFairChinRingsAbove + 2);

// Each vertex's distance in edges from the nearest of `from[i]` where `among[i]` holds
// (breadth-first; a large number where none is reachable).
std::vector<int> edge_hops(const std::vector<std::set<int>>& ring, const std::vector<int>& from, const std::vector<char>& among) {
  std::vector<int> hops(ring.size(), std::numeric_limits<int>::max() / 2);
  std::vector<int> queue;
  for (size_t i = 0; i < from.size(); ++i)
    if (among[i]) { hops[static_cast<size_t>(from[i])] = 0; queue.push_back(from[i]); }
  for (size_t at = 0; at < queue.size(); ++at)
    for (int n : ring[static_cast<size_t>(queue[at])])
      if (hops[static_cast<size_t>(n)] > hops[static_cast<size_t>(queue[at])] + 1) {
        hops[static_cast<size_t>(n)] = hops[static_cast<size_t>(queue[at])] + 1;
        queue.push_back(n);
      }
  return hops;
}

Fairing make_fairing() {
  Builder B;
  B.want_topology = true;
  build(plan_body(to_dims(typical_dimensions(Sex::Neutral)), Sex::Neutral), B);
  add_landmarks(B);
  std::set<int> pinned;
  for (const auto& [name, id] : B.landmarks) pinned.insert(id);
  Fairing f;
  const Vec3 free(1, 1, 1), level(1, 0, 1);  // level: keeps its ring's height
  auto take = [&](int l, int r, const Vec3& freedom, double w = 1.0, bool hole_bottom = false, double fill = 1.0) {
    if (l < 0 || pinned.count(l) || pinned.count(r)) return;
    f.left.push_back(l);
    f.right.push_back(r);
    f.freedom.push_back(freedom);
    f.weight.push_back(w);
    f.hole_bottom.push_back(hole_bottom);
    f.fill.push_back(fill);
  };
  // Faired only: the jaw and the groin have no armpit folds to fill.
  auto take_unfilled = [&](int l, int r, const Vec3& freedom) { take(l, r, freedom, 1.0, false, 0.0); };
  const int kax = torso_key_ring(kAxilla);
  // From the hole's bottom edge up: left out, its corners stayed sharp, a notch in front of and
  // behind the armpit. That edge keeps its height (free to rise, it folded over the ring under
  // it where the armpit sits close above the chest). Its folds are not filled (filled, the edge
  // moved out past the chest's breadth on bodies whose chest lies just under it, and folded
  // against the arm's first ring), and the filling fades in over the kFoldFillFade edges above
  // it: filled in full next to it, the surface stood out over the edge in a fold.
  for (int k = kax; k <= torso_key_ring(kShoulder2); ++k)
    for (int j = kHoleJ0 - kFairColumns; j <= kHoleJ1 + kFairColumns; ++j)
      take(B.torso[static_cast<size_t>(k)][static_cast<size_t>(j)], B.torso[static_cast<size_t>(k)][static_cast<size_t>(kTorsoN - j)],
           k > kax ? free : level, 1.0, k == kax);
  // The arm's first rings move fully, the next ones less and less: where the faired rings met
  // the first fixed one, a ring showed round the upper arm (in the rest pose most).
  for (int r = 1; r <= kFairArmRings + kFairArmTaper; ++r) {
    const double w = r <= kFairArmRings ? 1.0 : static_cast<double>(kFairArmRings + kFairArmTaper + 1 - r) / (kFairArmTaper + 1);
    for (int q = 0; q < kArmN; ++q)
      take(B.arm[0][static_cast<size_t>(r)][static_cast<size_t>(q)], B.arm[1][static_cast<size_t>(r)][static_cast<size_t>(q)], free, w);
  }
  // Under the jaw: the chin ring stands several centimetres in front of the neck's rings and
  // often less than a centimetre above the cervicale ring, so the neck's front met the floor of
  // the mouth along the cervicale ring at about 85° on the typical bodies, and the floor met the
  // face along the chin ring: a mask's rim from the chin back to the jaw's angle in every
  // three-quarter and side view. Six rings (were three) between the two and the fairing of the
  // front of the head from the cervicale ring (level: the neck ring, which carries the girth, lies under it)
  // to two rings above the chin's round both edges off. No measure lies there (the head's are on
  // the glabella ring); the relief (sculpt()) draws the chin and lips afterwards. Points on the
  // midline stay on it.
  for (int k = torso_key_ring(kCervicale); k <= torso_key_ring(kChin) + kFairChinRingsAbove; ++k)
    for (int j = 0; j <= kFairChinColumns; ++j) {
      const Vec3 freedom = k == torso_key_ring(kCervicale) ? level : free;
      take_unfilled(B.torso[static_cast<size_t>(k)][static_cast<size_t>(j)], B.torso[static_cast<size_t>(k)][static_cast<size_t>((kTorsoN - j) % kTorsoN)],
                    j == 0 ? Vec3(0, freedom.y(), 1) : freedom);
    }
  // The groin: where one torso ring around both thighs meets a tube around each thigh, the
  // torso's bottom rings stand out over the thighs' front-lateral quarter and the surface folds
  // along a horizontal line (a shorts hem). Fairing the two bottom torso rings and the legs' first
  // two rings (the thigh girth ring below them stays) rounds that fold off. Horizontally only: the
  // rings there lie under a centimetre apart, and moving them up or down folds them over each
  // other on heavy bodies. Not the inner thigh beside the crotch bridge, whose fold between the
  // legs would sharpen.
  std::set<int> seen(f.left.begin(), f.left.end());
  auto take_once = [&](int l, int r) { if (seen.insert(l).second) take_unfilled(l, r, level); };
  for (int k = 0; k < kFairGroinTorsoRings; ++k)
    for (int j = 1; j < kTorsoN / 2; ++j)
      take_once(B.torso[static_cast<size_t>(k)][static_cast<size_t>(j)], B.torso[static_cast<size_t>(k)][static_cast<size_t>(kTorsoN - j)]);
  for (int r = 0; r < kFairGroinLegRings; ++r)
    for (int q = 1; q < kLegBridgeFirst - 1; ++q) take_once(B.leg[0][static_cast<size_t>(r)][static_cast<size_t>(q)], B.leg[1][static_cast<size_t>(r)][static_cast<size_t>(q)]);
  const std::vector<std::set<int>> ring = one_rings(B);
  const std::vector<int> hops = edge_hops(ring, f.left, f.hole_bottom);
  for (size_t i = 0; i < f.left.size(); ++i)
    if (f.fill[i] > 0) f.fill[i] = std::min(1.0, hops[static_cast<size_t>(f.left[i])] / static_cast<double>(kFoldFillFade));
  std::vector<std::vector<std::array<int, 3>>> around(B.v.size());
  for (const auto& t : B.faces)
    for (int c : t) around[static_cast<size_t>(c)].push_back(t);
  for (int id : f.left) {
    f.neighbours.emplace_back(ring[static_cast<size_t>(id)].begin(), ring[static_cast<size_t>(id)].end());
    f.faces.push_back(around[static_cast<size_t>(id)]);
  }
  return f;
}

// The share of each step the armpit hole's bottom edge takes: fairing moves it out a little,
// which widens the chest section where the chest level lies just under the armpit (1–2 cm on
// bodies whose ANSUR axilla is at or below their chest height), so there it fades out.
double hole_bottom_share(const BodyPlan& P, const Dims& d) {
  const double sc = d.S / 1.70;
  const double chest_gap = P.torso[static_cast<size_t>(torso_key_ring(kAxilla))].y - P.torso[static_cast<size_t>(torso_key_ring(kChest))].y;
  return smoothstep(1.5 * 0.01 * sc, 3.0 * 0.01 * sc, chest_gap);
}

// The umbrella operator: from a vertex to the mean of its one-ring.
Vec3 umbrella(const Fairing& f, size_t i, const std::vector<Vec3>& v) {
  Vec3 mean = Vec3::Zero();
  for (int n : f.neighbours[i]) mean += v[static_cast<size_t>(n)];
  return mean / static_cast<double>(f.neighbours[i].size()) - v[static_cast<size_t>(f.left[i])];
}

// The outward unit normal at a vertex: its faces' normals weighted by their areas.
Vec3 vertex_normal(const Fairing& f, size_t i, const std::vector<Vec3>& v) {
  Vec3 n = Vec3::Zero();
  for (const auto& t : f.faces[i]) {
    const Vec3& a = v[static_cast<size_t>(t[0])];
    n += (v[static_cast<size_t>(t[1])] - a).cross(v[static_cast<size_t>(t[2])] - a);
  }
  return n.normalized();
}

// Runs `iterations` steps of `step_of(it, i)` for every free vertex at once, each masked by the
// vertex's freedom and scaled by its weight.
template <class StepOf>
void move_free(const Fairing& f, std::vector<Vec3>& v, double hole_bottom_share, int iterations, StepOf step_of) {
  std::vector<Vec3> step(f.left.size());
  for (int it = 0; it < iterations; ++it) {
    for (size_t i = 0; i < f.left.size(); ++i) step[i] = step_of(it, i).cwiseProduct(f.freedom[i]);
    for (size_t i = 0; i < f.left.size(); ++i)
      v[static_cast<size_t>(f.left[i])] += f.weight[i] * (f.hole_bottom[i] ? hole_bottom_share : 1.0) * step[i];
  }
}

void fair(std::vector<Vec3>& v, double hole_bottom_share) {
  static const Fairing f = make_fairing();
  move_free(f, v, hole_bottom_share, 2 * kFairIterations, [&](int it, size_t i) -> Vec3 {
    const double factor = it % 2 == 0 ? 0.5 : -0.53;  // λ, μ (|μ| > λ: no shrinking)
    return factor * umbrella(f, i, v);
  });
  // The folds filled: outward only, half the normal part of the umbrella operator per step.
  move_free(f, v, hole_bottom_share, kFoldFillIterations, [&](int, size_t i) -> Vec3 {
    if (f.fill[i] == 0) return Vec3::Zero();
    const Vec3 n = vertex_normal(f, i, v);
    return 0.5 * f.fill[i] * std::max(0.0, umbrella(f, i, v).dot(n)) * n;
  });
  for (size_t i = 0; i < f.left.size(); ++i) v[static_cast<size_t>(f.right[i])] = mirror(v[static_cast<size_t>(f.left[i])]);
}

// ---- Relief: anatomy drawn on the lofted surface -------------------------------
// The rings give the body its measured girths, breadths and depths but no anatomy: an egg of a
// head, a torso with a flat front. sculpt() moves torso, head and leg vertices horizontally
// along their ring's outward normal by a sum of smooth, compactly supported bumps ((1 − r²)³
// kernels) placed in each body's own frame (head features in units of its head length, torso
// features from its key levels and breadths, knees and ankles from the leg rings), so every
// feature scales with the body. Fidelity is kept by construction:
//  * the motion is horizontal, so no vertex changes height (every height target and every ring
//    level stays);
//  * landmark vertices do not move, except the few that only fix a section's height (chest,
//    neck, knee, malleolus), which move horizontally;
//  * on every horizontal section that carries a breadth or depth (chest, waist, hip/buttock),
//    vertices on the plane or on an edge crossing it move only inward, and the features there
//    are concave and away from the section's extreme points (grooves between the pectorals and
//    along the spine, a navel beside the omphalion); on girth-only sections (neck, head; thigh,
//    lower thigh, calf, ankle), whose every vertex is on the hull, nothing moves;
//  * around the waist the spine groove is paired with the erector muscles beside it, which rise
//    at most to the ring's own back extreme, so the waist's depth is unchanged;
//  * the groin's filling (fill_groin) moves vertices outward only strictly between the thigh's
//    girth ring and the hip ring;
//  * one exception: the groin's fold crosses the hip ring's section, and its groove shortens that
//    section's hull (the buttock girth) by up to 1.1 mm, under the 1 % tolerance.
// Before the relief, flat ring panels are re-spaced along their own polyline
// (respace_torso_columns), so the features have vertices to move.
// The left half is computed and mirrored, so bodies stay exactly symmetric.
namespace {

// A grid of vertex ids (rings × columns, −1 = none) with its triangulation's neighbours.
struct Grid {
  const std::vector<std::vector<int>>* ids;
  bool closed_columns = true;
  int id(int r, int c) const {
    const auto& R = (*ids)[static_cast<size_t>(r)];
    const int n = static_cast<int>(R.size());
    return R[static_cast<size_t>(((c % n) + n) % n)];
  }
  int rings() const { return static_cast<int>(ids->size()); }
  int columns() const { return static_cast<int>((*ids)[0].size()); }
};

// The outward horizontal normal of a ring running along t (its columns' order), or 0.
Vec3 outward_across(const Vec3& t) {
  const Vec3 n(-t.z(), 0, t.x());
  return n.norm() > 1e-12 ? Vec3(n / n.norm()) : Vec3(0, 0, 0);
}

// The ring's outward horizontal normal at (r, c), from the neighbouring columns.
Vec3 ring_normal(const Grid& g, const std::vector<Vec3>& v, int r, int c) {
  const int a = g.id(r, c - 1), b = g.id(r, c + 1), m = g.id(r, c);
  const Vec3 pa = v[static_cast<size_t>(a >= 0 ? a : m)], pb = v[static_cast<size_t>(b >= 0 ? b : m)];
  return outward_across(pb - pa);
}

// Vertices on a horizontal plane y = ys or on a grid edge that crosses it (their motion moves
// the section there). Edges: along rings, across rings, and the quads' (r, c)–(r+1, c+1) diagonal.
void mark_section(const Grid& g, const std::vector<Vec3>& v, double ys, int r0, int r1, std::vector<char>& on) {
  auto side = [&](int id) { const double d = v[static_cast<size_t>(id)].y() - ys; return std::abs(d) < 1e-12 ? 0 : (d > 0 ? 1 : -1); };
  for (int r = std::max(0, r0); r <= std::min(g.rings() - 1, r1); ++r)
    for (int c = 0; c < g.columns(); ++c) {
      const int a = g.id(r, c);
      if (a < 0) continue;
      const int sa = side(a);
      if (sa == 0) { on[static_cast<size_t>(a)] = 1; continue; }
      const std::array<std::pair<int, int>, 6> nb = {{{r, c + 1}, {r, c - 1}, {r + 1, c}, {r - 1, c}, {r + 1, c + 1}, {r - 1, c - 1}}};
      for (const auto& [rr, cc] : nb) {
        if (rr < 0 || rr >= g.rings()) continue;
        const int b = g.id(rr, cc);
        if (b >= 0 && side(b) == -sa) { on[static_cast<size_t>(a)] = 1; break; }
      }
    }
}

// The frame the head's features are laid out in: head centimetres (head length / 19.5 cm) from
// the glabella ring, vertically scaled by the face's height (glabella to chin) as a share of its
// usual 13.06 head centimetres (less where a short neck lifts the chin ring).
struct HeadFrame {
  double hu = 0, face = 1, y_g = 0, cz = 0;
  double X(double x) const { return x / hu; }
  double Y(double y) const { return (y - y_g) / (hu * face); }
  double Z(double z) const { return (z - cz) / hu; }
};
HeadFrame head_frame(const BodyPlan& P, const Dims& d) {
  const TorsoRing& glabella = P.torso[static_cast<size_t>(torso_key_ring(kGlabella))];
  HeadFrame H;
  H.hu = 0.01 * d.headl / 0.195;
  H.y_g = glabella.y;
  H.cz = glabella.cz;
  H.face = std::clamp((H.y_g - P.torso[static_cast<size_t>(torso_key_ring(kChin))].y) / (13.06 * H.hu), 0.3, 1.0);
  return H;
}

// Near the ear (1 over it, fading to 0 a little beyond): where its columns are denser.
double ear_zone(double Y, double Z) {
  return (1 - smoothstep(1.0, 2.4, std::abs(Y - kEarY) / kEarRY)) * (1 - smoothstep(1.0, 1.6, std::abs(Z - kEarZ) / kEarRZ));
}

// Where X lies across the eye: −1 at its inner corner, 0 at its middle, 1 at its outer corner.
double eye_across(double X) { return (X - kEyeX) / kEyeHalfWidth; }

// The upper and the lower lid's line (their heights Y) at X.
std::pair<double, double> lids(double X) {
  const double s = std::clamp(eye_across(X), -1.0, 1.0), w = 1 - s * s, mid = kEyeY + 0.05 * s;
  return {mid + kEyeUp * w * (1 - 0.25 * s), mid - kEyeDown * w * (1 + 0.2 * s)};
}

// How far (X, Y) lies under the upper lid's line and over the lower lid's, measured across each
// line, not straight down: toward the corners the lines are steep, and there a vertical
// distance made the margins slivers that the columns cut into teeth.
std::pair<double, double> inside_lids(double X, double Y) {
  const double e = 0.01;
  const auto [up, down] = lids(X);
  const auto [up0, down0] = lids(X - e);
  const auto [up1, down1] = lids(X + e);
  return {(up - Y) / std::hypot(1.0, (up1 - up0) / (2 * e)), (Y - down) / std::hypot(1.0, (down1 - down0) / (2 * e))};
}

// The eye's opening (the palpebral fissure), in head centimetres: 1 inside, 0 outside, over the
// lids' margins kEyeMargin wide. An almond 2·kEyeHalfWidth from corner to corner; the upper lid's
// arch is highest toward the nose, the lower lid's lowest toward the ear, and the outer corner
// lies a little higher than the inner.
double eye_opening(double X, double Y) {
  if (std::abs(eye_across(X)) >= 1) return 0.0;
  const auto [to_up, to_down] = inside_lids(X, Y);
  return smoothstep(0, kEyeMargin, to_up) * smoothstep(0, kEyeMargin, to_down);
}

// The upper lid's rim over its margin (head centimetres): 1 over the lid's line, on a band
// kLidRimWidth wide just over it (and 0.05 either side), 0 away from it, thinning toward the
// corners.
double upper_lid_rim(double X, double Y) {
  const double s = eye_across(X);
  if (std::abs(s) >= 1) return 0.0;
  const double over = -inside_lids(X, Y).first;
  return blob(over - 0.5 * kLidRimWidth, 0, 0.5 * kLidRimWidth + 0.05, 1) * (1 - s * s);
}

// The face's relief, head centimetres outward, at (X, Y) head centimetres from the glabella (X
// across from the midline, Y up; sculpt() fades it out toward the head's sides).
double face_height(double X, double Y) {
  double f = 0;
  // Brow ridge, under the glabella ring, ending level at it (that ring carries the head's
  // measures and does not move: a ridge that stops short of it shades a line across the forehead).
  f += 0.42 * blob(X - 2.9, Y + 1.3, 2.8, 1.3);
  // Eye socket: deep under the brow, shallow under the eye, so the lower lid runs on into
  // the cheek (a socket as deep below as above left a dark band under each eye and a
  // bright one across the cheekbones: a face in stripes).
  {
    const double dy = Y + 2.35;
    f -= 0.55 * blob(X - kEyeX, dy, 1.9, dy < 0 ? 0.9 : 1.35);
  }
  // The eyeball under the lids, about 3.5 head-cm across (a blob is flat only over about half
  // its radius); the opening between the lids is eye_opening()'s, 2.9 head-cm wide.
  f += 0.42 * blob(X - kEyeX, Y + 2.7, 1.75, 0.95);  // the eyeball, under the lids
  // The opening between the lids, the eye behind their margins, and the cornea's bulge. On the
  // face's fine rings the margins are crisp lines round an almond; before those (until
  // 2026-11-29) the grid was about 4 mm across and 2.5 mm high, and blobs drew a slit.
  // The eye behind the opening curves back toward the corners as a ball does (recessed evenly,
  // it was lit as evenly as the lids round it: a blank almond), and the upper lid's margin has
  // a rim, the lid's thickness, thinning toward the corners.
  const double s_eye = std::clamp(eye_across(X), -1.0, 1.0);
  f -= (kEyeRecess * (1 + kEyeCornerRecess * s_eye * s_eye) - 0.04 * blob(X - kEyeX, Y - kEyeY, 0.9, 0.6)) * eye_opening(X, Y);
  f += kLidRim * upper_lid_rim(X, Y);
  f -= 0.12 * blob(X - 3.0, Y + 2.0, 1.7, 0.45);   // the upper lid's crease
  f += 0.10 * blob(X - 5.2, Y + 2.6, 0.9, 1.8);    // the socket's outer rim: the eyes are not a band
  f -= 0.25 * blob(X, Y + 1.6, 1.4, 0.8);          // nasion
  // Nose: a bridge rising from the nasion to the tip, the tip's underside back to the lip.
  {
    const double y_top = -1.4, y_tip = -5.4, y_base = -6.9, height = 1.6;
    double prof = 0;
    if (Y <= y_top && Y >= y_tip) prof = std::pow((y_top - Y) / (y_top - y_tip), 1.3);
    else if (Y < y_tip && Y > y_base) prof = 1 - smoothstep(0.0, 1.0, (y_tip - Y) / (y_tip - y_base));
    const double half = std::lerp(1.1, 2.0, std::clamp((y_top - Y) / (y_top - y_tip), 0.0, 1.0));
    f += height * prof * blob(X, 0, half, 1);
    // The tip's rounded end, a third of the nose's height: the bridge's ramp alone ended in
    // a corner, a spike in profile (2.3 high with a 0.55 tip, until 2026-11-28).
    f += 0.85 * blob(X, Y + 5.5, 1.5, 1.5);
    {  // the nostrils' wings, easing down into the upper lip (a sharp lower edge shaded a moustache)
      // Their middles 1.4 head-cm from the midline, so the nose's base is about 3.7 cm wide, as
      // a real one is: at 1.7 with radius 1 (until 2026-11-28) it was 4.4 cm, a ball on each
      // side of a thin nose.
      const double dy = Y + 5.9;
      f += 0.55 * blob(X - kAlaX, dy, kAlaRadius, dy < 0 ? 1.6 : 0.9);
      // the alar groove round each wing's top and back, which sets it off the cheek
      f -= 0.07 * (blob(X - kAlaX, Y + 5.6, 1.6, 1.3) - blob(X - kAlaX, Y + 5.6, 1.15, 0.9));
    }
  }
  // No hollow under the cheekbone: the head rings' own curve carries the face round to the
  // ears, and a relief falling back from the midline had to rise again where the front
  // weight ends, a trough that made the face a skull's. No cheekbone ridge either: its
  // lit top and shaded underside drew one more band across the face; the cheek is one
  // round fullness.
  // The cheek, under the eye: full beside the nose and the mouth's corners it rounded into
  // a grin (0.40 at Y = −6.0).
  f += 0.28 * blob(X - 3.2, Y + 5.3, 2.0, 2.4);
  f += 0.40 * blob(X - 4.8, Y + 7.2, 2.4, 3.0);    // the cheek's side over the jaw (no gaunt hollow)
  // The muzzle: the teeth's arch carries the mouth forward as a whole, the cheeks round
  // into it (without it the lips sat on a flat plate and the nose's shadow ran out
  // sideways as a grin).
  f += 0.45 * blob(X, Y + 8.4, 3.6, 3.0);
  // Lips: each rises slowly from the skin and drops steeply into the mouth line, so the upper
  // lip faces down and the lower lip up, as real ones do (rounded both ways, each lip was lit
  // as a bar across the face); both thin out toward the corners.
  auto lip = [&](double dy, double rx, double ry_up, double ry_down) {
    return blob(X, dy, rx, (dy > 0 ? ry_up : ry_down) * std::sqrt(std::max(0.2, 1 - sq(X / rx))));
  };
  // The mouth about 5 cm wide (at radii 2.1 and 1.9 it was a child's pout under a grin).
  // The lips' line bends down toward the corners, 8 mm at 2.5 head-cm out (kMouthDroop):
  // drawn level on a face that curves back, it read as a grin from in front (until
  // 2026-11-28). Its middle 2 head-cm stay level: bent there too, the mouth line crossed
  // the rings at the midline and pinched (the head's largest angle 108° → 129° over the
  // development subset; 111° on one mean body, 88° level).
  auto droop = [](double across) { return kMouthDroop * sq(std::max(0.0, across - kMouthLevelHalf)); };
  const double Ym = Y + droop(X);
  f += 0.38 * lip(Ym + 8.2, 2.6, 1.4, 0.35);       // upper lip
  f += 0.40 * lip(Ym + 8.85, 2.3, 0.4, 0.95);      // lower lip
  f -= 0.18 * lip(Ym + 8.5, 2.7, 0.25, 0.25);      // mouth line, about as wide as the lips
  f -= 0.10 * blob(X, Y + 7.0, 0.45, 0.9);         // the philtrum's groove
  f -= 0.08 * blob(X - 2.7, Y + droop(2.7) + 8.5, 0.8, 0.8);  // mouth corners, lowered whole
  f -= 0.22 * blob(X, Y + 10.3, 1.7, 0.7);         // labiomental fold (2.2 wide, it drew a grin's line)
  f += 0.50 * blob(X, Y + 11.8, 2.2, 1.4);         // chin
  // No jaw line of its own: the lifted chin ring is the mandible's lower border, faired
  // into the floor of the mouth (make_fairing()). A ridge along it over a hollow under it
  // drew the border as a crisp line from the chin to the ear, a mask's rim.
  return f;
}

// The ear's height off the side of the head, head centimetres: a shell standing out most at its
// back edge (its front is the cheek's), with a rim (the helix) round its top and back, the
// lobe without one, and a bowl (the concha) in front of the rim's lower half. A shell and one
// hollow, as before 2026-11-28, read as a bump on the head.
double ear_height(double Y, double Z) {
  const double u = (Y - kEarY) / kEarRY, w = (Z - kEarZ) / kEarRZ, r = std::hypot(u, w);
  if (r >= 1) return 0.0;
  const double back = smoothstep(-1.0, 1.0, -w);
  const double shell = (1 - smoothstep(0.55, 1.0, r)) * (0.7 + 0.5 * back);
  const double front_low = (1 - smoothstep(-0.1, 0.4, u)) * smoothstep(-0.1, 0.4, w);
  const double rim = blob(r - 0.7, 0, 0.3, 1) * (1 - front_low) * smoothstep(-0.75, -0.45, u);
  const double bowl = blob(u + 0.1, w - 0.1, 0.42, 0.48);
  return shell + 0.35 * rim - 0.7 * bowl;
}

// Squarish rings (hips reach superellipse exponent 6, a chest's back 8) sample their flat front and back
// with hardly a vertex: column 1 sits at 0.7 of the half-breadth, so a groove or a pectoral has
// nothing to move. Each ring's front (columns 0–8) and back (24–32), and the head's rings all
// round, are re-spaced along the ring's own polyline, at equal steps of length plus a share for the turning angle (corners keep more
// columns): the vertices stay on the polyline, so the ring keeps its extreme points and, up to the
// corners' chords (< 0.1 % of a girth), its hull. Landmark columns and the ends stay in place.
void respace_torso_columns(Builder& B, const std::set<int>& pinned, const HeadFrame& H) {
  std::vector<Vec3>& v = B.v;
  const int nt = static_cast<int>(B.torso.size());
  for (int k = 1; k < nt; ++k) {
    const auto& R = B.torso[static_cast<size_t>(k)];
    // The head (above the cervicale ring) all round: its boxiest rings would leave the ears
    // between columns.
    const bool head = k > torso_key_ring(kCervicale);
    // The face gets denser columns than the back and sides of the head: its features (eyes, nose
    // wings, lips) are 1–3 cm wide, and at the head's even 9 mm spacing an eye had three columns.
    // Edges in front cost more, fading from the glabella ring up the dome (whose forehead
    // carries no feature) so the columns do not shear against the face's.
    // Under the jaw the weight fades in from the cervicale ring: the rings there lie close in
    // height but centimetres apart in depth, and columns spaced differently on neighbouring
    // rings fold the floor of the mouth.
    const int kg = torso_key_ring(kGlabella), kcv = torso_key_ring(kCervicale), kch = torso_key_ring(kChin);
    const double face_weight = !head ? 0.0
                                     : kFaceDensity * std::clamp(1.0 - double(k - kg) / (kDomeRings / 2), 0.0, 1.0) *
                                           std::clamp(double(k - kcv) / (kch + 2 - kcv), 0.0, 1.0);
    const std::vector<std::pair<int, int>> spans = head ? std::vector<std::pair<int, int>>{{0, 16}, {16, 32}}
                                                        : std::vector<std::pair<int, int>>{{0, 6}, {26, 32}};
    for (const auto& [j0, j1] : spans) {
      int a = j0;
      while (a < j1) {
        int b = a + 1;
        while (b < j1 && !pinned.count(R[static_cast<size_t>(b)])) ++b;
        if (b - a >= 2) {
          bool whole = true;
          for (int j = a; j <= b; ++j) whole = whole && R[static_cast<size_t>(j)] >= 0;
          if (whole) {
            std::vector<Vec3> q;
            for (int j = a; j <= b; ++j) q.push_back(v[static_cast<size_t>(R[static_cast<size_t>(j)])]);
            const double scale = 0.25 * (q.back() - q.front()).norm();
            double half = 0;  // the ring's half-breadth on this span
            for (const Vec3& p : q) half = std::max(half, std::abs(p.x()));
            std::vector<double> cost(q.size(), 0.0);
            for (size_t i = 1; i < q.size(); ++i) {
              double turn = 0;
              for (size_t e : {i - 1, i}) {  // turning at both ends of the edge, halved
                if (e == 0 || e + 1 >= q.size()) continue;
                const Vec3 u = (q[e] - q[e - 1]).normalized(), w = (q[e + 1] - q[e]).normalized();
                turn += 0.5 * std::acos(std::clamp(u.dot(w), -1.0, 1.0));
              }
              const double face = j0 == 0 ? 1 - smoothstep(0.55, 0.85, 0.5 * std::abs(q[i].x() + q[i - 1].x()) / std::max(half, 1e-9)) : 0.0;
              // Around the ears too: a rim and a bowl need columns about 4 mm apart, not 9.
              const Vec3 mid = 0.5 * (q[i] + q[i - 1]);
              const double ear = head ? kEarDensity * ear_zone(H.Y(mid.y()), H.Z(mid.z())) : 0.0;
              cost[i] = cost[i - 1] + (q[i] - q[i - 1]).norm() * (1 + face_weight * face + ear) + scale * turn;
            }
            size_t e = 1;
            for (int j = a + 1; j < b; ++j) {
              const double want = cost.back() * (j - a) / (b - a);
              while (e + 1 < q.size() && cost[e] < want) ++e;
              const double f = (want - cost[e - 1]) / std::max(1e-15, cost[e] - cost[e - 1]);
              v[static_cast<size_t>(R[static_cast<size_t>(j)])] = q[e - 1] + f * (q[e] - q[e - 1]);
            }
          }
        }
        a = b;
      }
    }
    for (int j = 1; j < kTorsoN / 2; ++j)
      if (R[static_cast<size_t>(j)] >= 0) v[static_cast<size_t>(R[static_cast<size_t>(kTorsoN - j)])] = mirror(v[static_cast<size_t>(R[static_cast<size_t>(j)])]);
  }
}

// The fine rings' halfway vertices, once the columns are re-spaced: on the chord between their
// columns, so the surface is the one the columns make and only the relief (sculpt()) draws finer.
// (On the cubic through the four nearest columns, the fine rings stood fuller than the coarse
// ones over them by a tenth of a millimetre, and the temples showed a line along the glabella
// ring.) Left half; the right is its mirror.
void place_fine(Builder& B) {
  for_each_fine(B, [&](int k, int j, int id, int mirror_id) {
    const Vec3 p = 0.5 * (B.v[static_cast<size_t>(B.torso_at(k, j))] + B.v[static_cast<size_t>(B.torso_at(k, j + 1))]);
    B.v[static_cast<size_t>(id)] = p;
    B.v[static_cast<size_t>(mirror_id)] = mirror(p);
  });
}

// -- The relief of torso, neck and head (sculpt()).
// Where one body's relief goes: its key levels and breadths, and its units, from its plan.
struct ReliefFrame : ChestFrame {
  HeadFrame H;  // the face's own units (head centimetres)
  double y_hip = 0, y_s2 = 0, y_nk = 0, y_cv = 0;  // more key rings
  double y_gf = 0, y_crotch = 0;  // the gluteal furrow, the crotch
  double a_sh = 0, a_hip = 0;     // half-breadths: shoulders' top, hip
  double thigh_out = 0;                  // the thigh's outer side at its girth ring
  // The iliac crest's front (its anterior spine), (x, y); and the groin's fold, from the thigh's
  // inner front beside the crotch up and out to it.
  Eigen::Vector2d iliac_front, groin0;
  double groin_fold_x(double y) const {
    return std::lerp(groin0.x(), iliac_front.x(), std::clamp((y - groin0.y()) / (iliac_front.y() - groin0.y()), 0.0, 1.0));
  }
};

ReliefFrame relief_frame(const BodyPlan& P, const Dims& d, Sex sex, const Builder& B) {
  ReliefFrame F;
  auto ring_y = [&](int key) { return P.torso[static_cast<size_t>(torso_key_ring(key))].y; };
  static_cast<ChestFrame&>(F) =
      chest_frame(sex, d.S / 1.70, ring_y(kWaist), ring_y(kUnderBust), ring_y(kChest), ring_y(kAxilla), ring_y(kHoleTop));
  F.H = head_frame(P, d);
  F.y_hip = ring_y(kHip);
  F.y_s2 = ring_y(kShoulder2);
  F.y_nk = ring_y(kNeck);
  F.y_cv = ring_y(kCervicale);
  F.y_gf = B.v[static_cast<size_t>(B.landmarks.at("gluteal_furrow"))].y();
  F.y_crotch = P.crotch_y;
  F.a_ch = P.torso[static_cast<size_t>(torso_key_ring(kChest))].a;
  F.a_sh = P.torso[static_cast<size_t>(torso_key_ring(kHoleTop))].a;
  F.a_hip = P.torso[static_cast<size_t>(torso_key_ring(kHip))].a;
  const LegRing& thigh_ring = P.leg[static_cast<size_t>(leg_key_ring(kThigh))];
  F.thigh_out = thigh_ring.xc + thigh_ring.al;
  F.iliac_front = Eigen::Vector2d(0.78 * F.a_hip, F.y_hip + 0.45 * (F.y_w - F.y_hip));
  F.groin0 = Eigen::Vector2d(thigh_ring.xc - 0.5 * thigh_ring.am, P.crotch_y + 1.0 * F.cm);
  return F;
}

// Each of the next three adds its features' heights (metres, outward) to h at a point (x from the
// midline, height y) of the left half; `front` and `back` fade from 1 on the torso's front or
// back to 0 at its sides.

// The face and the ears, above C7 (p on ring k, column jf, fractional on the face's fine rings).
void add_head_relief(const ReliefFrame& F, const BodyPlan& P, const Vec3& p, int k, double jf, double& h) {
  const double x = std::abs(p.x()), y = p.y();
  // The face, in head centimetres from the glabella (X across, Y up; face_height()).
  const double X = F.H.X(x), Y = F.H.Y(y);
  // Faded out toward the head's sides by the point's place across its ring, not by its
  // column: the face's columns are respaced (respace_torso_columns), so a column's index
  // no longer says where it lies.
  const double face_front = jf <= kTorsoN / 4 ? 1 - smoothstep(0.78, 0.98, x / P.torso[static_cast<size_t>(k)].a) : 0.0;
  h += face_front * face_height(X, Y) * F.H.hu;
  // Ears, on the head's sides (by place, not column: the ears' columns are respaced too).
  const double side = smoothstep(0.55, 0.85, x / P.torso[static_cast<size_t>(k)].a);
  h += side * ear_height(Y, F.H.Z(p.z())) * F.H.hu;
}

// The front: the groove down the sternum, pectorals or the folds under the breasts, clavicles,
// the rib cage's lower border, the iliac crest's front, the groin, the navel.
void add_front_relief(const ReliefFrame& F, double x, double y, double front, double& h) {
  const double cm = F.cm;
  add_chest_relief(F, x, y, front, h);
  // Clavicles: a ridge from the sternum to the shoulder, hollows above and below it.
  const double x0 = 1.8 * cm, x1 = F.a_sh - 4.0 * cm;
  if (x1 > x0) {
    const double u = std::clamp((x - x0) / (x1 - x0), 0.0, 1.0);
    const double ycl = F.y_acr - 2.4 * cm + 1.6 * cm * u;
    const double along_cl = window(x, x0 - 1 * cm, x0 + 1 * cm, x1 - 1.5 * cm, x1 + 0.5 * cm);
    h += front * along_cl * 0.30 * cm * blob(y - ycl, 0, 2.0 * cm, 1);
    h -= front * 0.60 * cm * blob(x - (x0 + 0.55 * (x1 - x0)), y - (ycl + 2.8 * cm), 0.35 * (x1 - x0), 2.0 * cm) *
         (1 - smoothstep(F.y_nk - 2.5 * cm, F.y_nk - 0.5 * cm, y));  // not into the neck's girth
    h -= front * 0.30 * cm * blob(x - (x0 + 0.7 * (x1 - x0)), y - (ycl - 3.2 * cm), 0.3 * (x1 - x0), 1.8 * cm);
  }
  // The rib cage's lower border: an inverted V from the sternum's tip out to the flanks,
  // the belly below it a little hollow.
  {
    const double yr = F.y_us + 2.0 * cm - 6.0 * cm * std::min(1.0, x / (0.8 * F.a_ch));
    const double dy = yr - y;  // > 0 below the border
    const double below = dy > 0 ? blob(dy - 2.0 * cm, 0, 3.0 * cm, 1) : 0.0;
    h -= front * (0.25 - 0.1 * F.fem) * cm * below * window(x, 1.0 * cm, 3.0 * cm, 0.75 * F.a_ch, 0.95 * F.a_ch) *
         smoothstep(F.y_w + 1.5 * cm, F.y_w + 4 * cm, y);
  }
  // The front of the iliac crest (its anterior spine), between the hip and waist sections.
  {
    const double ry = 0.3 * (F.y_w - F.y_hip);
    h += front * std::min(0.25 * cm, 0.12 * ry) * blob(x - F.iliac_front.x(), y - F.iliac_front.y(), 2.5 * cm, ry);
  }
  // The groin: the fold where the thigh's front meets the lower belly, from beside the crotch
  // up and out toward the iliac crest's front. Without it the belly ended in a level line
  // across both thighs, the hem of a pair of shorts.
  {
    const Eigen::Vector2d e = F.iliac_front - F.groin0, q(x, y);
    const double u = std::clamp((q - F.groin0).dot(e) / e.squaredNorm(), 0.0, 1.0);
    const double dist = (q - (F.groin0 + u * e)).norm();
    h -= front * std::lerp(0.5, 0.4, F.fem) * cm * window(u, 0.0, 0.3, 0.75, 1.0) * blob(dist, 0, 2.0 * cm, 1);
  }
  // Navel: a dimple just under the omphalion (which keeps its place and depth).
  h -= front * 0.45 * cm * blob(x, y - (F.y_w - 0.9 * cm), 1.6 * cm, 1.0 * cm);
}

// The back: the lower back's hollow, the gluteal folds, the shoulder blades (the spine's groove
// is drawn ring by ring in sculpt()).
void add_back_relief(const ReliefFrame& F, double x, double y, double back, double& h) {
  const double cm = F.cm;
  // The lower back's hollow above the waist (its section untouched).
  {
    const double ry = 0.45 * (F.y_us - F.y_w);
    h -= back * 0.35 * cm * blob(x, y - 0.5 * (F.y_w + F.y_us), 0.55 * F.a_ch, ry);
  }
  // Gluteal fold: under each buttock over the back of the thigh, curving under the cheek (u: the
  // share of the way out to the thigh's outer side). Falling toward the side, as until
  // 2026-12-07, it ended each cheek in a level line with a corner at its outer end (two cushions).
  {
    const double xe = F.thigh_out, u = std::min(1.0, x / xe), um = kFoldLowest;
    const double rise = u < um ? kFoldRiseMedial * sq((um - u) / um) : kFoldRiseLateral * sq((u - um) / (1 - um));
    const double yf = F.y_gf - kFoldDrop * cm + rise * cm;
    const double dy = y - yf;
    const double prof = dy > 0 ? blob(dy, 0, 2.0 * cm, 1) : blob(dy, 0, 3.0 * cm, 1);
    // A seat that hangs down to the crotch leaves the fold no room: it fades out there.
    h -= back * 0.55 * cm * smoothstep(2.0 * cm, 5.0 * cm, F.y_gf - F.y_crotch) * prof * window(x, 1.0 * cm, 3.5 * cm, 0.75 * xe, 0.95 * xe);
  }
  // Shoulder blades.
  const double ys = F.y_ch + 0.55 * (F.y_acr - F.y_ch), ry = std::max(0.5 * cm, 0.4 * (F.y_acr - F.y_ch));
  h += back * 0.8 * cm * blob(x - 0.42 * F.a_ch, y - ys, 0.32 * F.a_ch, ry);
}

// The relief's height (metres, outward) at p on ring k, column jf of the left half (fractional
// on the face's fine rings).
double torso_relief(const ReliefFrame& F, const BodyPlan& P, const Vec3& p, int k, double jf) {
  const double t = 2 * kPi * jf / kTorsoN, c = std::cos(t), s = std::sin(t);
  const double x = std::abs(p.x()), y = p.y();
  const double front = front_share(t), back = smoothstep(0.25, 0.65, -c);
  double h = 0;
  if (y > F.y_cv) add_head_relief(F, P, p, k, jf, h);
  add_front_relief(F, x, y, front, h);
  // The neck's base: the ring under the neck flares less, so the neck flows into the
  // trapezius and the collarbones instead of standing on a collar.
  h -= 0.35 * F.cm * blob(y - F.y_s2, 0, F.y_nk - F.y_s2, 1) * smoothstep(0.15, 0.6, s);
  add_back_relief(F, x, y, back, h);
  return h;
}

// The groin, filled outside its fold. Where the belly's lowest rings hug the thighs they fell up
// to 8 mm behind the thigh's front below them and the hip ring above (the thigh is a round tube,
// the torso's rings one superellipse round both): a level groove across the front, the hem of a
// pair of shorts. Outward of the groin's fold line (fold_x(y): its distance from the midline at
// height y), their front comes forward to the straight line between the thigh's girth ring and
// the hip ring (neither moves; at most 1 cm); inward of it the lower belly keeps its fold, which
// so runs up and out along the groin, as a real one does. Adds to D (torso grid T, left leg L;
// v0 the surface and N its ring normals before the relief).
void fill_groin(const BodyPlan& P, const Grid& T, const Grid& L, const std::vector<Vec3>& v0, const std::vector<Vec3>& N,
                double y_hip, double cm, const std::function<double(double)>& fold_x, std::vector<double>& D) {
  const int kh = torso_key_ring(kHip), kth = leg_key_ring(kThigh);
  const double y_th = P.leg[static_cast<size_t>(kth)].y;
  // A ring's points as z over x (x increasing), and z at x on them (NaN beyond their ends).
  auto sorted_by_x = [&](const std::vector<int>& ids) {
    std::vector<Eigen::Vector2d> q;
    for (int id : ids) q.emplace_back(v0[static_cast<size_t>(id)].x(), v0[static_cast<size_t>(id)].z());
    std::sort(q.begin(), q.end(), [](const auto& a, const auto& b) { return a.x() < b.x(); });
    return q;
  };
  auto z_at = [](const std::vector<Eigen::Vector2d>& q, double x) {
    if (q.size() < 2 || x < q.front().x() || x > q.back().x()) return std::numeric_limits<double>::quiet_NaN();
    const auto hi = std::lower_bound(q.begin(), q.end(), x, [](const auto& a, double at) { return a.x() < at; });
    if (hi == q.begin()) return hi->y();
    const auto lo = hi - 1;
    return std::lerp(lo->y(), hi->y(), (x - lo->x()) / std::max(1e-12, hi->x() - lo->x()));
  };
  std::vector<int> thigh_ids, hip_ids;
  for (int k = 0; k < kLegN; ++k)
    if (std::cos(leg_angle(k)) > 0) thigh_ids.push_back(L.id(kth, k));
  for (int j = 0; j < kTorsoN / 4; ++j)
    if (T.id(kh, j) >= 0) hip_ids.push_back(T.id(kh, j));
  const auto thigh = sorted_by_x(thigh_ids), hip = sorted_by_x(hip_ids);  // their front halves
  auto fill = [&](int id, double c, double share) {
    const Vec3& p = v0[static_cast<size_t>(id)];
    if (c <= 0.2 || p.y() <= y_th || p.y() >= y_hip) return;
    const double zt = z_at(thigh, p.x()), zh = z_at(hip, p.x());
    if (std::isnan(zt) || std::isnan(zh)) return;
    const double gap = std::lerp(zt, zh, (p.y() - y_th) / (y_hip - y_th)) - p.z();
    const double x_fold = fold_x(p.y());
    if (gap > 0 && N[static_cast<size_t>(id)].z() > 0)
      D[static_cast<size_t>(id)] += share * smoothstep(0.2, 0.5, c) * smoothstep(x_fold - 1.0 * cm, x_fold + 4.0 * cm, p.x()) *
                                    std::min(gap, 1.0 * cm);
  };
  for (int k = 0; k < kh; ++k)
    for (int j = 0; j < kTorsoN / 4; ++j)
      if (T.id(k, j) >= 0) fill(T.id(k, j), std::cos(2 * kPi * j / kTorsoN), 1.0);
  // On the thigh's first ring, only its outer half: moved beside the crotch bridge, its inner
  // front folded against the bridge's top (123° on one man, from 112°).
  for (int r = 1; r < kth; ++r)
    for (int k = 0; k < kLegN; ++k)
      if (L.id(r, k) >= 0) fill(L.id(r, k), std::cos(leg_angle(k)), smoothstep(-0.1, 0.4, std::sin(leg_angle(k))));
}

// The knee's and the ankle's relief at p, column k of a left leg ring (metres, outward): the
// kneecap and the tendons beside it, the inner thigh's teardrop, the hollow behind the knee, the
// Achilles tendon's hollows and the malleoli, placed by the knee and malleolus rings.
double leg_relief(const ReliefFrame& F, const LegRing& knee, const LegRing& mall, const Vec3& p, int k) {
  const double phi = leg_angle(k), c = std::cos(phi), s = std::sin(phi);
  const double xl = p.x() - knee.xc, zl = p.z() - mall.zc, y = p.y();
  const double y_kn = knee.y, y_ml = mall.y, cm = F.cm;
  double h = 0;
  // Kneecap, with the hollows beside the patellar tendon below it.
  const double fr = smoothstep(0.2, 0.6, c);
  h += fr * 0.50 * cm * blob(xl, y - (y_kn + 0.6 * cm), 2.8 * cm, 4.5 * cm);
  h -= fr * 0.30 * cm * (blob(xl - 2.3 * cm, y - (y_kn - 2.6 * cm), 1.4 * cm, 1.6 * cm) +
                         blob(xl + 2.3 * cm, y - (y_kn - 2.6 * cm), 1.4 * cm, 1.6 * cm));
  // The inner thigh's teardrop (vastus medialis) over the knee's inner side, filling the span
  // from the knee ring to the lower thigh's girth ring above it (centred 5 cm up with a 4 cm
  // reach, as it was under that ring at 11 cm, it crossed the ring at 6 cm, which does not move:
  // a line round the inner thigh); the hollow behind the knee between the hamstrings' tendons,
  // centred 1 cm above the knee ring and ending below that girth ring.
  const double teardrop = 0.5 * kLowerThighOverKnee / 0.01 * cm;  // its centre's height over the knee, and its reach
  h += smoothstep(0.2, 0.8, -s) * smoothstep(-0.4, 0.3, c) * 0.45 * cm * blob(0, y - (y_kn + teardrop), 1, teardrop);
  h -= smoothstep(0.5, 0.9, -c) * 0.45 * cm * blob(xl, y - (y_kn + 1.0 * cm), 3.0 * cm, 4.5 * cm);
  // The hollows either side of the Achilles tendon, behind the malleoli.
  const double beside_tendon = std::exp(-sq((std::abs(std::remainder(phi, 2 * kPi)) - (kPi - 0.75)) / 0.3));
  h -= beside_tendon * 0.35 * cm * blob(0, y - y_ml, 1, 3.5 * cm);
  // Malleoli: the lateral one lower and further back than the medial one.
  h += smoothstep(0.5, 0.9, s) * 0.40 * cm * blob(zl + 0.3 * cm, y - (y_ml + 0.6 * cm), 2.2 * cm, 2.2 * cm);
  h += smoothstep(0.5, 0.9, -s) * 0.35 * cm * blob(zl - 0.3 * cm, y - (y_ml + 1.4 * cm), 2.2 * cm, 2.2 * cm);
  return h;
}

void sculpt(const BodyPlan& P, const Dims& d, Sex sex, Builder& B) {
  // The frame reads the gluteal furrow's height before the columns are re-spaced: landmarks are
  // pinned there, and re-spacing keeps every ring's level.
  const ReliefFrame F = relief_frame(P, d, sex, B);
  const double cm = F.cm;  // one centimetre on a 1.70 m body
  std::vector<Vec3>& v = B.v;
  {
    std::set<int> pinned;
    for (const auto& [name, id] : B.landmarks) pinned.insert(id);
    respace_torso_columns(B, pinned, F.H);
    place_fine(B);
  }
  const std::vector<Vec3> v0 = v;
  std::vector<double> D(v.size(), 0.0);      // outward displacement, metres
  std::vector<double> ridge(v.size(), 0.0);  // the erector muscles' share of it (see above)
  std::vector<Vec3> N(v.size(), Vec3::Zero());

  // -- Torso, neck and head (left half, j = 0..32): torso_relief().
  const Grid T{&B.torso};
  const int nt = T.rings();
  for (int k = 0; k < nt; ++k)
    for (int j = 0; j <= kTorsoN / 2; ++j) {
      const int id = T.id(k, j);
      if (id < 0) continue;
      N[static_cast<size_t>(id)] = ring_normal(T, v0, k, j);
      D[static_cast<size_t>(id)] = torso_relief(F, P, v0[static_cast<size_t>(id)], k, j);
    }
  // The fine rings' halfway vertices, each moved along its chord's outward normal.
  for_each_fine(B, [&](int k, int j, int id, int) {
    N[static_cast<size_t>(id)] = outward_across(v0[static_cast<size_t>(T.id(k, j + 1))] - v0[static_cast<size_t>(T.id(k, j))]);
    D[static_cast<size_t>(id)] = torso_relief(F, P, v0[static_cast<size_t>(id)], k, j + 0.5);
  });
  // The spine groove and the erector muscles beside it, ring by ring (see the section comment).
  for (int k = 0; k < nt; ++k) {
    const double yk = P.torso[static_cast<size_t>(k)].y;
    const double depth = window(yk, F.y_hip + 1 * cm, std::max(F.y_w - 1 * cm, F.y_hip + 6 * cm), F.y_cv - 10 * cm, F.y_cv - 3 * cm) *
                         std::lerp(0.45 * cm, 0.60 * cm, 1 - smoothstep(F.y_us, F.y_ch, yk));
    if (depth <= 0) continue;
    double back_extreme = 1e9;
    for (int j = kTorsoN / 4; j <= kTorsoN / 2; ++j)
      if (T.id(k, j) >= 0) back_extreme = std::min(back_extreme, v0[static_cast<size_t>(T.id(k, j))].z());
    for (int j = kTorsoN / 4 + 1; j <= kTorsoN / 2; ++j) {
      const int id = T.id(k, j);
      if (id < 0) continue;
      const Vec3& p = v0[static_cast<size_t>(id)];
      const double x = std::abs(p.x());
      const double groove = depth * blob(x, 0, 4.0 * cm, 1);
      D[static_cast<size_t>(id)] -= groove;
      const double room = p.z() - back_extreme;  // how far this point lies inside the back's extreme
      // Only around the waist, whose depth is a target: elsewhere the groove may deepen the back.
      const double near_waist = blob(p.y() - F.y_w, 0, 7 * cm, 1);
      ridge[static_cast<size_t>(id)] = near_waist * room * depth / (room + depth + 1e-12) * blob(x - 4.2 * cm, 0, 3.4 * cm, 1);
    }
  }

  // -- Legs (left leg; ring 0 is the torso's bottom ring).
  const Grid L{&B.leg[0]};
  const int knee_r = leg_key_ring(kKnee), mall_r = leg_key_ring(kMalleolus);
  const LegRing &knee = P.leg[static_cast<size_t>(knee_r)], &mall = P.leg[static_cast<size_t>(mall_r)];
  for (int r = 1; r < L.rings(); ++r)
    for (int k = 0; k < kLegN; ++k) {
      const int id = L.id(r, k);
      if (id < 0) continue;  // a toe's hole
      N[static_cast<size_t>(id)] = ring_normal(L, v0, r, k);
      D[static_cast<size_t>(id)] = leg_relief(F, knee, mall, v0[static_cast<size_t>(id)], k);
    }

  fill_groin(P, T, L, v0, N, F.y_hip, cm, [&](double y) { return F.groin_fold_x(y); }, D);

  // -- Arms (left arm, T-posed along +X): the deltoid's cap. Over the shoulder's outside the
  // arm's rings ran straight on from the torso's slope, a doll's square shoulder. The muscle
  // rounds the top, front and back of the upper arm, not its underside: it rises from the
  // acromion (a landmark, which stays), is fullest a quarter to a third of the way to the biceps
  // ring and is gone before that ring (whose girth is a target). Steeper, it drew a line across
  // the shoulder's top.
  const Grid Ar{&B.arm[0]};
  {
    const double x_acr = v0[static_cast<size_t>(B.landmarks.at("acromion_left"))].x();
    const double x_bi = v0[static_cast<size_t>(B.landmarks.at("biceps_left"))].x();
    const double len = x_bi - x_acr;
    const double amp = std::lerp(0.8, 0.6, F.fem) * cm;
    for (int r = 1; r < Ar.rings(); ++r) {
      Vec3 centre = Vec3::Zero();
      for (int q = 0; q < kArmN; ++q) centre += v0[static_cast<size_t>(Ar.id(r, q))];
      centre /= kArmN;
      if (centre.x() > x_bi) break;
      for (int q = 0; q < kArmN; ++q) {
        const int id = Ar.id(r, q);
        const Vec3& p = v0[static_cast<size_t>(id)];
        Vec3 n(0, p.y() - centre.y(), p.z() - centre.z());
        if (n.norm() < 1e-12) continue;
        n.normalize();
        N[static_cast<size_t>(id)] = n;
        const double along = window(p.x(), x_acr, x_acr + 0.25 * len, x_acr + 0.35 * len, x_acr + 0.85 * len);
        D[static_cast<size_t>(id)] = amp * along * smoothstep(-0.4, 0.5, n.y());
      }
    }
  }

  // -- Guards: sections that carry targets move only inward; landmarks stay.
  // Sections with a breadth or depth: grooves may cross them between the extreme points.
  // Girth-only sections (neck, head, leg girths), whose every ring vertex is on the hull: none.
  std::vector<char> on(v.size(), 0), girth_only(v.size(), 0);
  auto lm = [&](const char* name) { return B.landmarks.at(name); };
  auto ly = [&](const char* name) { return v0[static_cast<size_t>(lm(name))].y(); };
  for (const char* name : {"chest_front", "omphalion", "hip_left", "buttock_back"}) mark_section(T, v0, ly(name), 0, nt - 1, on);
  for (const char* name : {"neck_front", "glabella"}) mark_section(T, v0, ly(name), 0, nt - 1, girth_only);
  for (const char* name : {"thigh_left", "lower_thigh_left", "calf_left", "ankle_left"})
    mark_section(L, v0, ly(name), 1, L.rings() - 1, girth_only);
  for_each_fine(B, [&](int k, int j, int id, int) {  // a halfway vertex as its columns
    for (auto* marks : {&on, &girth_only}) {
      auto& m = *marks;
      m[static_cast<size_t>(id)] = m[static_cast<size_t>(T.id(k, j))] || m[static_cast<size_t>(T.id(k, j + 1))];
    }
  });
  for (size_t i = 0; i < v.size(); ++i)
    D[i] = girth_only[i] ? 0.0 : (on[i] ? std::min(D[i], 0.0) : D[i]) + ridge[i];
  const std::set<std::string> height_only = {"chest_front", "thelion_left", "thelion_right", "neck_front", "knee_left", "knee_right",
                                             "lateral_malleolus_left", "lateral_malleolus_right"};
  for (const auto& [name, id] : B.landmarks)
    if (!height_only.count(name)) D[static_cast<size_t>(id)] = 0;

  // -- Apply on the left, mirror to the right.
  for (int k = 0; k < nt; ++k)
    for (int j = 0; j <= kTorsoN / 2; ++j) {
      const int id = T.id(k, j);
      if (id < 0) continue;
      v[static_cast<size_t>(id)] = v0[static_cast<size_t>(id)] + D[static_cast<size_t>(id)] * N[static_cast<size_t>(id)];
      if (j == 0 || j == kTorsoN / 2) v[static_cast<size_t>(id)].x() = 0;
      else v[static_cast<size_t>(T.id(k, kTorsoN - j))] = mirror(v[static_cast<size_t>(id)]);
    }
  for_each_fine(B, [&](int, int, int id, int mirror_id) {
    v[static_cast<size_t>(id)] = v0[static_cast<size_t>(id)] + D[static_cast<size_t>(id)] * N[static_cast<size_t>(id)];
    v[static_cast<size_t>(mirror_id)] = mirror(v[static_cast<size_t>(id)]);
  });
  // A limb: its left side moved, the right side its mirror (ids −1: a toe's or the thumb's hole).
  auto apply_limb = [&](const Grid& left, const std::vector<std::vector<int>>& right) {
    for (int r = 1; r < left.rings(); ++r)
      for (int c = 0; c < left.columns(); ++c) {
        const int id = left.id(r, c);
        if (id < 0) continue;
        v[static_cast<size_t>(id)] = v0[static_cast<size_t>(id)] + D[static_cast<size_t>(id)] * N[static_cast<size_t>(id)];
        v[static_cast<size_t>(right[static_cast<size_t>(r)][static_cast<size_t>(c)])] = mirror(v[static_cast<size_t>(id)]);
      }
  };
  apply_limb(L, B.leg[1]);
  apply_limb(Ar, B.arm[1]);
}

}  // namespace

const Topology& topology() {
  static const Topology topo = make_topology();
  return topo;
}

// ---- UV layout ----------------------------------------------------------------------------
// Every part of the body is a stack of rings, so each part is unwrapped the way a tailor
// flattens a sleeve: cut along one or more columns (seams), each piece between two seams an
// island with u = arc length around each ring from its first seam (centred) and v = distance
// along the stack (the mean distance between consecutive rings). Each strip of quads between two
// rings then lies between two horizontal lines with its columns in order, so no island folds
// over itself, and lengths around and along the body are kept (areas roughly so; a closing pole
// is the point above its ring's centre, the sinusoidal projection's equal-area trick). Cutting
// the torso and legs into front and back halves halves the shear where rings shrink fast (top
// of the shoulders, top of the head, foot). Soles are flat: their UVs are their footprint.
// Islands keep one scale (metres), are skyline-packed (quarter turns allowed) and scaled into
// [0, 1]² with a margin.
namespace {

const Builder& ring_structure() {  // the rings and face order of topology()
  static const Builder structure = [] {
    Builder B;
    B.want_topology = true;
    build(plan_body(to_dims(typical_dimensions(Sex::Neutral)), Sex::Neutral), B);
    return B;
  }();
  return structure;
}

struct RingStack {
  const std::vector<std::vector<int>>* rings = nullptr;  // [ring][column], −1 inside a hole
  std::vector<int> seams;  // the columns cut open, increasing; one island between each two
  int pole = -1;           // the vertex closing the last ring, or −1
  bool downward = false;   // v decreases along the stack (legs and arms: feet and hands down)
  const Builder* halfway_of = nullptr;  // the torso's builder: its fine rings' halfway vertices (Builder::fine)
  int fine_at(int r, int c) const { return halfway_of ? halfway_of->fine_at(r, c) : -1; }
};

struct IslandUv {
  std::vector<Eigen::Vector2d> uv;         // metres, island-local
  std::vector<std::array<int, 3>> corners; // per face of the island: indices into uv
};

// Unwraps faces [f0, f1) of the topology, all between consecutive rings of `S` or fanning to its
// pole, into one island per pair of consecutive seams; island_of[f − f0] tells each face's.
// Places round a ring are counted in half columns: 2c is column c, 2c + 1 a fine ring's vertex
// halfway to column c + 1.
std::vector<IslandUv> unwrap_stack(const RingStack& S, const Vertices& rest, const std::vector<std::array<int, 3>>& faces,
                                   size_t f0, size_t f1, std::vector<int>& island_of) {
  const auto& R = *S.rings;
  const int nr = static_cast<int>(R.size()), n = static_cast<int>(R[0].size());
  // Positions, a missing vertex (a hole) interpolated between the rings around the hole.
  std::vector<std::vector<Vec3>> P(static_cast<size_t>(nr), std::vector<Vec3>(static_cast<size_t>(n)));
  auto at = [&](int r, int c) { return R[static_cast<size_t>(r)][static_cast<size_t>(c)]; };
  for (int c = 0; c < n; ++c)
    for (int r = 0; r < nr; ++r) {
      if (at(r, c) >= 0) {
        P[static_cast<size_t>(r)][static_cast<size_t>(c)] = rest.row(at(r, c)).transpose();
        continue;
      }
      int r0 = r, r1 = r;
      while (r0 > 0 && at(r0, c) < 0) --r0;
      while (r1 + 1 < nr && at(r1, c) < 0) ++r1;
      const Vec3 a = rest.row(at(r0, c)).transpose(), b = rest.row(at(r1, c)).transpose();
      P[static_cast<size_t>(r)][static_cast<size_t>(c)] = a + (b - a) * (static_cast<double>(r - r0) / (r1 - r0));
    }
  std::vector<double> v(static_cast<size_t>(nr), 0.0);
  for (int r = 1; r < nr; ++r) {
    double d = 0;
    for (int c = 0; c < n; ++c) d += (P[static_cast<size_t>(r)][static_cast<size_t>(c)] - P[static_cast<size_t>(r - 1)][static_cast<size_t>(c)]).norm();
    v[static_cast<size_t>(r)] = v[static_cast<size_t>(r - 1)] + d / n;
  }
  // Island p runs from column a = seams[p] over len columns to the next seam (all n for one).
  const int parts = static_cast<int>(S.seams.size());
  auto first = [&](int p) { return S.seams[static_cast<size_t>(p)]; };
  auto length = [&](int p) { return parts == 1 ? n : (first((p + 1) % parts) - first(p) + n) % n; };
  // u[p][r][h]: arc length around ring r from column a to half column 2a + h (h = 0..2 len), centred.
  std::vector<std::vector<std::vector<double>>> u(static_cast<size_t>(parts));
  for (int p = 0; p < parts; ++p) {
    const int a = first(p), len = length(p);
    u[static_cast<size_t>(p)].assign(static_cast<size_t>(nr), std::vector<double>(static_cast<size_t>(2 * len + 1), 0.0));
    for (int r = 0; r < nr; ++r) {
      auto& ur = u[static_cast<size_t>(p)][static_cast<size_t>(r)];
      const auto& Pr = P[static_cast<size_t>(r)];
      for (int k = 1; k <= len; ++k) {
        const int c0 = (a + k - 1) % n;
        const Vec3 &p0 = Pr[static_cast<size_t>(c0)], &p1 = Pr[static_cast<size_t>((a + k) % n)];
        const auto h = static_cast<size_t>(2 * k);
        if (const int mid = S.fine_at(r, c0); mid >= 0) {
          const Vec3 m = rest.row(mid).transpose();
          ur[h - 1] = ur[h - 2] + (m - p0).norm();
          ur[h] = ur[h - 1] + (p1 - m).norm();
        } else {
          const double chord = (p1 - p0).norm();
          ur[h - 1] = ur[h - 2] + 0.5 * chord;
          ur[h] = ur[h - 2] + chord;
        }
      }
      const double half = 0.5 * ur[static_cast<size_t>(2 * len)];
      for (double& x : ur) x -= half;
    }
  }
  double pole_v = v.back();
  if (S.pole >= 0) {
    double d = 0;
    for (int c = 0; c < n; ++c) d += (rest.row(S.pole).transpose() - P.back()[static_cast<size_t>(c)]).norm();
    pole_v += d / n;
  }
  const double sign = S.downward ? -1.0 : 1.0;
  std::map<int, std::pair<int, int>> where;  // vertex → (ring, half column)
  for (int r = 0; r < nr; ++r)
    for (int c = 0; c < n; ++c) {
      if (at(r, c) >= 0) where[at(r, c)] = {r, 2 * c};
      if (const int mid = S.fine_at(r, c); mid >= 0) where[mid] = {r, 2 * c + 1};
    }
  std::vector<IslandUv> out(static_cast<size_t>(parts));
  std::vector<std::map<std::pair<int, int>, int>> uv_index(static_cast<size_t>(parts));  // (ring, k) → uv; ring nr = the pole
  auto uv_of = [&](int p, int r, int k) {
    auto& island = out[static_cast<size_t>(p)];
    auto [it, fresh] = uv_index[static_cast<size_t>(p)].try_emplace({r, k}, static_cast<int>(island.uv.size()));
    if (fresh)
      island.uv.push_back(r == nr ? Eigen::Vector2d(0, sign * pole_v)
                                  : Eigen::Vector2d(u[static_cast<size_t>(p)][static_cast<size_t>(r)][static_cast<size_t>(k)],
                                                    sign * v[static_cast<size_t>(r)]));
    return it->second;
  };
  auto is_seam = [&](int c) { return std::find(S.seams.begin(), S.seams.end(), c) != S.seams.end(); };
  island_of.clear();
  for (size_t f = f0; f < f1; ++f) {
    std::array<std::pair<int, int>, 3> rc{};  // (ring, half column); ring nr = the pole
    int part = -1;
    for (int i = 0; i < 3; ++i) {
      const int id = faces[f][static_cast<size_t>(i)];
      rc[static_cast<size_t>(i)] = id == S.pole ? std::pair<int, int>{nr, 0} : where.at(id);
      const int h = rc[static_cast<size_t>(i)].second;
      if (id == S.pole || (h % 2 == 0 && is_seam(h / 2))) continue;
      for (int p = 0; p < parts; ++p) {  // the island whose columns hold this corner
        const int k = (h - 2 * first(p) + 2 * n) % (2 * n);
        if (k > 0 && k < 2 * length(p)) part = p;
      }
    }
    if (part < 0) throw Error(ErrorKind::Format, "uv_layout: a face lies on seams only", "faces");  // not in this topology
    const int a = first(part), len = length(part);
    std::array<int, 3> k{};
    bool far = false;
    for (int i = 0; i < 3; ++i) {
      k[static_cast<size_t>(i)] = (rc[static_cast<size_t>(i)].second - 2 * a + 2 * n) % (2 * n);
      far = far || (rc[static_cast<size_t>(i)].first < nr && k[static_cast<size_t>(i)] > len);
    }
    std::array<int, 3> corner{};
    for (int i = 0; i < 3; ++i) {
      const int r = rc[static_cast<size_t>(i)].first;
      int ki = r == nr ? 0 : k[static_cast<size_t>(i)];
      if (r < nr && ki == 0 && far) ki = 2 * len;  // the island's closing seam
      corner[static_cast<size_t>(i)] = uv_of(part, r, ki);
    }
    out[static_cast<size_t>(part)].corners.push_back(corner);
    island_of.push_back(part);
  }
  return out;
}

// A flat island: the faces projected on the plane of two axes (the soles' footprint on the floor:
// x, z; the webs between the fingers: z, y).
IslandUv unwrap_flat(const Vertices& rest, const std::vector<std::array<int, 3>>& faces, size_t f0, size_t f1,
                     int axis_u, int axis_v) {
  IslandUv out;
  std::map<int, int> uv_index;
  for (size_t f = f0; f < f1; ++f) {
    std::array<int, 3> corner{};
    for (int i = 0; i < 3; ++i) {
      const int id = faces[f][static_cast<size_t>(i)];
      auto [it, fresh] = uv_index.try_emplace(id, static_cast<int>(out.uv.size()));
      if (fresh) out.uv.emplace_back(rest(id, axis_u), rest(id, axis_v));
      corner[static_cast<size_t>(i)] = it->second;
    }
    out.corners.push_back(corner);
  }
  return out;
}

double signed_area(const IslandUv& island) {
  double total = 0;
  for (const auto& c : island.corners) {
    const Eigen::Vector2d a = island.uv[static_cast<size_t>(c[0])], b = island.uv[static_cast<size_t>(c[1])],
                          d = island.uv[static_cast<size_t>(c[2])];
    total += (b - a).x() * (d - a).y() - (b - a).y() * (d - a).x();
  }
  return 0.5 * total;
}

}  // namespace

UvLayout uv_layout(const Vertices& rest) {
  const Builder& B = ring_structure();
  if (rest.rows() != static_cast<Eigen::Index>(B.v.size()))
    throw Error(ErrorKind::InvalidArgument,
                "uv_layout: expected the topology's " + std::to_string(B.v.size()) + " vertices, got " +
                    std::to_string(rest.rows()), "vertices");
  // Islands in order, with the pair each belongs to (a quarter turn applies to a whole pair).
  std::vector<IslandUv> islands;
  std::vector<int> pair_of;
  std::vector<std::pair<size_t, size_t>> face_at(B.faces.size());  // face → (island, its index there)
  for (size_t i = 0; i < B.island_starts.size(); ++i) {
    const auto [f0, id] = B.island_starts[i];
    const size_t f1 = i + 1 < B.island_starts.size() ? B.island_starts[i + 1].first : B.faces.size();
    RingStack S;
    int pair = 0;
    if (id == kIslandTorso) {
      S = {&B.torso, {kTorsoN / 4, 3 * kTorsoN / 4}, B.head_pole, false, &B};  // front and back, cut at the sides
    } else if (id == kIslandLeg || id == kIslandLeg + 1) {  // front and back, cut at the inseam and outseam
      S = {&B.leg[static_cast<size_t>(id - kIslandLeg)], {kLegLateral, kLegMedial}, -1, true};
      pair = 1;
    } else if (id == kIslandArm || id == kIslandArm + 1) {  // a sleeve cut under the arm, to the webs
      const int sd = id - kIslandArm;
      S = {&B.arm[static_cast<size_t>(sd)], {kArmBottom}, -1, true};
      pair = 3;
    } else if (id == kIslandThumb || id == kIslandThumb + 1) {  // digits: cut along their base loop's first column
      const int sd = id - kIslandThumb;
      S = {&B.thumb[static_cast<size_t>(sd)], {0}, B.thumb_pole[static_cast<size_t>(sd)], true};
      pair = 4;
    } else if (id >= kIslandFinger && id < kIslandFinger + 2 * kFingerCount) {
      const int sd = (id - kIslandFinger) / kFingerCount, f = (id - kIslandFinger) % kFingerCount;
      S = {&B.finger[static_cast<size_t>(sd)][static_cast<size_t>(f)], {0},
           B.finger_pole[static_cast<size_t>(sd)][static_cast<size_t>(f)], true};
      pair = 4;  // digits turn together
    } else if (id >= kIslandToe && id < kIslandToe + 2 * kToeCount) {
      const int sd = (id - kIslandToe) / kToeCount, t = (id - kIslandToe) % kToeCount;
      S = {&B.toe[static_cast<size_t>(sd)][static_cast<size_t>(t)], {0}, B.toe_pole[static_cast<size_t>(sd)][static_cast<size_t>(t)], true};
      pair = 4;
    } else {
      pair = 2;  // soles and webs
    }
    std::vector<IslandUv> parts;
    std::vector<int> part_of;
    if (S.rings) {
      parts = unwrap_stack(S, rest, B.faces, f0, f1, part_of);
    } else {
      const bool web = id == kIslandWeb || id == kIslandWeb + 1;
      parts = {unwrap_flat(rest, B.faces, f0, f1, web ? 2 : 0, web ? 1 : 2)};
      part_of.assign(f1 - f0, 0);
    }
    std::vector<size_t> next(parts.size(), 0);
    for (size_t f = f0; f < f1; ++f) {
      const auto p = static_cast<size_t>(part_of[f - f0]);
      face_at[f] = {islands.size() + p, next[p]++};
    }
    for (auto& part : parts) {
      // Faces run counter-clockwise seen from outside; so must their UVs (the right side's
      // islands come out mirrored, which is what mirroring the left's texture needs).
      if (signed_area(part) < 0)
        for (auto& p : part.uv) p.x() = -p.x();
      islands.push_back(std::move(part));
      pair_of.push_back(pair);
    }
  }

  // Skyline packing at one scale (bounding boxes): islands by decreasing height, each where its
  // top ends lowest (then leftmost) above the islands placed so far, within a strip of a given
  // width. Islands may turn a quarter turn (counter-clockwise, so their winding is kept), a left
  // and right pair together; the strip width and turns that give the smallest square win (no
  // turn on a tie).
  constexpr double kGap = 0.02;     // metres between islands
  constexpr double kMargin = 0.01;  // UV units around the atlas
  const size_t count_islands = islands.size();
  auto turned = [](const Eigen::Vector2d& p, bool turn) { return turn ? Eigen::Vector2d(-p.y(), p.x()) : p; };
  struct Segment { double x0, x1, y; };  // the skyline: height y over [x0, x1)
  auto pack = [&](double strip, const std::vector<Eigen::Vector2d>& size, const std::vector<size_t>& order,
                  std::vector<Eigen::Vector2d>& at) {
    std::vector<Segment> sky = {{0, strip + kGap, 0}};
    double width = 0, height = 0;
    for (size_t i : order) {
      const double w = size[i].x() + kGap;
      double best_top = 1e300, best_x = 0, best_y = 0;
      for (const Segment& start : sky) {
        if (start.x0 + w > strip + kGap + 1e-12) break;
        double y = 0;
        for (const Segment& g : sky)
          if (g.x1 > start.x0 && g.x0 < start.x0 + w) y = std::max(y, g.y);
        if (y + size[i].y() < best_top) { best_top = y + size[i].y(); best_x = start.x0; best_y = y; }
      }
      at[i] = {best_x, best_y};
      width = std::max(width, best_x + size[i].x());
      height = std::max(height, best_top);
      std::vector<Segment> next;
      const double x1 = best_x + w;
      for (const Segment& g : sky) {
        if (g.x0 < best_x) next.push_back({g.x0, std::min(g.x1, best_x), g.y});
        if (g.x1 > x1) next.push_back({std::max(g.x0, x1), g.x1, g.y});
      }
      next.push_back({best_x, x1, best_top + kGap});
      std::sort(next.begin(), next.end(), [](const Segment& a, const Segment& b) { return a.x0 < b.x0; });
      sky.clear();
      for (const Segment& g : next)
        if (g.x1 > g.x0) {
          if (!sky.empty() && sky.back().y == g.y) sky.back().x1 = g.x1;
          else sky.push_back(g);
        }
    }
    return std::max(width, height);
  };
  std::vector<Eigen::Vector2d> best(count_islands), lo(count_islands), size(count_islands);
  std::vector<bool> turn(count_islands, false);
  double best_side = 1e300;
  for (int combo = 0; combo < 32; ++combo) {
    std::vector<Eigen::Vector2d> lo_c(count_islands), size_c(count_islands), trial(count_islands);
    std::vector<bool> turn_c(count_islands);
    double widest = 0, total_width = 0;
    for (size_t i = 0; i < count_islands; ++i) {
      turn_c[i] = ((combo >> pair_of[i]) & 1) != 0;
      Eigen::Vector2d a = turned(islands[i].uv[0], turn_c[i]), b = a;
      for (const auto& p : islands[i].uv) a = a.cwiseMin(turned(p, turn_c[i])), b = b.cwiseMax(turned(p, turn_c[i]));
      lo_c[i] = a;
      size_c[i] = b - a;
      widest = std::max(widest, size_c[i].x());
      total_width += size_c[i].x() + kGap;
    }
    std::vector<size_t> order(count_islands);
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return size_c[a].y() > size_c[b].y(); });
    constexpr int kTrials = 200;
    for (int t = 0; t <= kTrials; ++t) {
      const double side = pack(widest + (total_width - widest) * t / kTrials, size_c, order, trial);
      if (side < best_side * (1 - 1e-9)) {
        best_side = side;
        best = trial;
        lo = lo_c;
        size = size_c;
        turn = turn_c;
      }
    }
  }
  // The skyline grows from the top of the atlas (v = 1, an image's first rows) down; islands
  // keep their orientation.
  const double scale = (1 - 2 * kMargin) / best_side;
  UvLayout layout;
  std::vector<int> offset(islands.size());
  Eigen::Index count = 0;
  for (size_t i = 0; i < islands.size(); ++i) {
    offset[i] = static_cast<int>(count);
    count += static_cast<Eigen::Index>(islands[i].uv.size());
  }
  layout.coordinates.resize(count, 2);
  for (size_t i = 0; i < islands.size(); ++i)
    for (size_t k = 0; k < islands[i].uv.size(); ++k) {
      const Eigen::Vector2d p = turned(islands[i].uv[k], turn[i]) - lo[i];  // in [0, size]
      const Eigen::Index row = offset[i] + static_cast<Eigen::Index>(k);
      layout.coordinates(row, 0) = std::clamp(kMargin + scale * (best[i].x() + p.x()), 0.0, 1.0);
      layout.coordinates(row, 1) = std::clamp(1 - kMargin - scale * (best[i].y() + size[i].y() - p.y()), 0.0, 1.0);
    }
  layout.faces.resize(static_cast<Eigen::Index>(B.faces.size()), 3);
  for (size_t f = 0; f < B.faces.size(); ++f) {
    const auto [i, at] = face_at[f];
    const auto& c = islands[i].corners[at];
    for (int k = 0; k < 3; ++k) layout.faces(static_cast<Eigen::Index>(f), k) = offset[i] + c[static_cast<size_t>(k)];
  }
  return layout;
}

// A relaxed stance: the legs lean out by kLegSplay, so the feet stand about hip-width apart
// instead of side by side with the thighs touching all the way down. Every vertex below the
// crotch moves straight outward by an amount that depends on its height alone, so each
// horizontal section of a leg moves as a whole: every girth, breadth, length and height stays.
// The lean starts gently (its slope grows over the first 10 cm below the crotch, per 1.70 m of
// stature, where the thighs meet the torso), and below the lateral malleolus the foot moves as one
// piece. Lengths along the leg grow by 1/cos(kLegSplay) − 1 = 0.24 %; no measured length does.
// Returns how far the foot moved out.
namespace {
double splay_legs(const BodyPlan& P, double sc, std::vector<Vec3>& v) {
  const double y_foot = P.leg[static_cast<size_t>(leg_key_ring(kMalleolus))].y;
  auto outward = [&](double y) { return splay_offset(y, P.crotch_y, y_foot, sc); };
  for (Vec3& p : v)
    if (p.y() < P.crotch_y && p.x() != 0) p.x() += (p.x() > 0 ? 1 : -1) * outward(p.y());
  return outward(y_foot);
}

// The toes turn out by kToeOut, each foot about the vertical through its leg's centre at the
// lateral malleolus (`foot_shift`: how far splay_legs() moved that centre out). The turn sets in
// from the ankle's section down to the malleolus' and is whole below it. Each horizontal section
// turns as a whole about a vertical axis, so every girth and height stays, and the foot's
// landmarks (heel, toe, its breadth's ends) all lie where the turn is whole, so its length and
// breadth stay too.
void turn_feet_out(const BodyPlan& P, double foot_shift, std::vector<Vec3>& v) {
  const LegRing& malleolus = P.leg[static_cast<size_t>(leg_key_ring(kMalleolus))];
  const double y_ankle = P.leg[static_cast<size_t>(leg_key_ring(kAnkle))].y;
  const double axis_x = malleolus.xc + foot_shift, axis_z = malleolus.zc;
  for (Vec3& p : v) {
    if (p.y() >= y_ankle || p.x() == 0) continue;
    const double side = p.x() > 0 ? 1 : -1;  // the left foot turns toward +x, the right toward −x
    const double t = side * kToeOut * (1 - smoothstep(malleolus.y, y_ankle, p.y()));
    const double dx = p.x() - side * axis_x, dz = p.z() - axis_z;
    p.x() = side * axis_x + dx * std::cos(t) + dz * std::sin(t);
    p.z() = axis_z - dx * std::sin(t) + dz * std::cos(t);
  }
}
}  // namespace

Vertices generate(const Dimensions& dims, Sex sex) {
  validate(dims, sex);
  const Dims d = to_dims(dims);
  const BodyPlan P = plan_body(d, sex);
  Builder B;
  build(P, B);
  fair(B.v, hole_bottom_share(P, d));
  add_landmarks(B);
  sculpt(P, d, sex, B);
  turn_feet_out(P, splay_legs(P, d.S / 1.70, B.v), B.v);
  Vertices out(static_cast<Eigen::Index>(B.v.size()), 3);
  for (size_t i = 0; i < B.v.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = B.v[i].transpose();
  return out;
}

std::vector<MeasurementDefinition> measurement_definitions() {
  using K = MeasurementKind;
  std::vector<MeasurementDefinition> d;
  auto add = [&](std::string name, K kind, std::vector<std::string> lm, Axis axis, std::string desc) {
    d.push_back({std::move(name), kind, std::move(lm), axis, std::move(desc)});
  };
  const Axis Y = Axis::Y, X = Axis::X;
  add("stature", K::Height, {"vertex"}, Y, "Floor to the top of the head");
  add("chest_height", K::Height, {"thelion_right"}, Y, "Floor to the bust point / nipple");
  add("waist_height", K::Height, {"omphalion"}, Y, "Floor to the navel");
  add("crotch_height", K::Height, {"crotch"}, Y, "Floor to the crotch (inseam)");
  add("cervicale_height", K::Height, {"cervicale"}, Y, "Floor to C7");
  add("acromial_height", K::Height, {"acromion_right"}, Y, "Floor to the acromion");
  add("axilla_height", K::Height, {"axilla_right"}, Y, "Floor to the armpit");
  add("iliocristale_height", K::Height, {"iliocristale_right"}, Y, "Floor to the iliac crest");
  add("trochanterion_height", K::Height, {"trochanterion_right"}, Y, "Floor to the trochanterion");
  add("buttock_height", K::Height, {"gluteal_furrow"}, Y, "Floor to the gluteal furrow");
  add("knee_height", K::Height, {"knee_right"}, Y, "Floor to mid-patella");
  add("lateral_malleolus_height", K::Height, {"lateral_malleolus_right"}, Y, "Floor to the lateral malleolus");
  add("biacromial_breadth", K::Length, {"acromion_left", "acromion_right"}, Y, "Acromion to acromion");
  add("chest_breadth", K::FrontBreadth, {"chest_front"}, Y, "Chest breadth at bust-point height, across the front");
  add("chest_depth", K::Depth, {"chest_front"}, Y, "Chest depth at bust-point height");
  add("waist_breadth", K::Breadth, {"omphalion"}, Y, "Waist breadth at the navel");
  add("waist_depth", K::Depth, {"omphalion"}, Y, "Waist depth at the navel");
  add("hip_breadth", K::Breadth, {"hip_left"}, Y, "Maximum hip breadth");
  add("buttock_depth", K::Depth, {"buttock_back"}, Y, "Buttock depth");
  add("span", K::Length, {"dactylion_left", "dactylion_right"}, Y, "Fingertip to fingertip, T-pose");
  add("wrist_span", K::Length, {"stylion_left", "stylion_right"}, Y, "Wrist to wrist, T-pose");
  add("arm_length", K::Length, {"acromion_right", "radiale_right", "stylion_right"}, Y, "Acromion–radiale–stylion");
  add("upper_arm_length", K::Length, {"acromion_right", "radiale_right"}, Y, "Acromion to radiale");
  add("forearm_length", K::Length, {"radiale_right", "stylion_right"}, Y, "Radiale to stylion");
  add("hand_length", K::Length, {"wrist_right", "dactylion_right"}, Y, "Wrist crease to middle fingertip");
  add("hand_breadth", K::Length, {"metacarpal_right", "metacarpal_ulnar_right"}, Y, "Hand breadth at the knuckles");
  add("foot_length", K::Length, {"heel_right", "toe_right"}, Y, "Heel to the tip of the longest toe");
  add("foot_breadth", K::Length, {"foot_medial_right", "foot_lateral_right"}, Y, "Foot breadth");
  add("head_breadth", K::Length, {"head_side_left", "head_side_right"}, Y, "Head breadth");
  add("head_length", K::Length, {"glabella", "opisthocranion"}, Y, "Glabella to the back of the head");
  add("chest_circumference", K::Circumference, {"chest_front"}, Y, "Chest (bust) circumference");
  add("waist_circumference", K::Circumference, {"omphalion"}, Y, "Waist circumference at the navel");
  add("buttock_circumference", K::Circumference, {"buttock_back"}, Y, "Buttock circumference");
  add("thigh_circumference", K::Circumference, {"thigh_right"}, Y, "Thigh circumference just below the crotch");
  add("lower_thigh_circumference", K::Circumference, {"lower_thigh_right"}, Y, "Lower thigh circumference");
  add("calf_circumference", K::Circumference, {"calf_right"}, Y, "Calf circumference");
  add("ankle_circumference", K::Circumference, {"ankle_right"}, Y, "Ankle circumference");
  add("neck_circumference", K::Circumference, {"neck_front"}, Y, "Neck circumference");
  add("head_circumference", K::Circumference, {"head_circumference_front"}, Y, "Head circumference");
  add("biceps_circumference", K::Circumference, {"biceps_right"}, X, "Upper arm circumference, relaxed");
  add("forearm_circumference", K::Circumference, {"forearm_right"}, X, "Forearm circumference, relaxed");
  add("wrist_circumference", K::Circumference, {"wrist_right"}, X, "Wrist circumference");
  add("weight", K::Weight, {}, Y, "a · volume + b");
  return d;
}

std::vector<FidelityTarget> fidelity_targets() {
  return {
      {"stature", "stature", false}, {"chest_height", "chestheight", false}, {"waist_height", "waistheightomphalion", false},
      {"crotch_height", "crotchheight", false}, {"cervicale_height", "cervicaleheight", false},
      {"acromial_height", "acromialheight", false}, {"axilla_height", "axillaheight", false},
      {"iliocristale_height", "iliocristaleheight", false}, {"trochanterion_height", "trochanterionheight", false},
      {"buttock_height", "buttockheight", false}, {"knee_height", "kneeheightmidpatella", false},
      {"lateral_malleolus_height", "lateralmalleolusheight", false}, {"biacromial_breadth", "biacromialbreadth", false},
      {"chest_breadth", "chestbreadth", false}, {"chest_depth", "chestdepth", false},
      {"waist_breadth", "waistbreadth", false}, {"waist_depth", "waistdepth", false}, {"hip_breadth", "hipbreadth", false},
      {"buttock_depth", "buttockdepth", false}, {"span", "span", false}, {"hand_length", "handlength", false},
      {"hand_breadth", "handbreadth", false}, {"foot_length", "footlength", false},
      {"foot_breadth", "footbreadthhorizontal", false}, {"head_breadth", "headbreadth", false},
      {"head_length", "headlength", false}, {"chest_circumference", "chestcircumference", true},
      {"waist_circumference", "waistcircumference", true}, {"buttock_circumference", "buttockcircumference", true},
      {"thigh_circumference", "thighcircumference", true}, {"lower_thigh_circumference", "lowerthighcircumference", true},
      {"calf_circumference", "calfcircumference", true}, {"ankle_circumference", "anklecircumference", true},
      {"neck_circumference", "neckcircumference", true}, {"head_circumference", "headcircumference", true},
      {"wrist_circumference", "wristcircumference", true}};
}

}  // namespace caliper::mannequin
