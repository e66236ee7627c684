// Landmarks on MakeHuman's hm08 body, chosen by geometry. Anthropometric meanings
// follow ANSUR II's definitions (Gordon et al. 2014); the rules are ours. All rules run on the
// reference body (default sliders, T-pose, feet on y = 0, facing +Z, +X = the body's left).
#include "caliper/makehuman/landmarks.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "caliper/body/body_model.h"
#include "caliper/errors.h"
#include "caliper/makehuman/body.h"
#include "caliper/mannequin/generator.h"

namespace caliper::makehuman {

namespace {

using Vec = Eigen::Vector3d;

struct Picker {
  const Vertices& v;
  const Vertices& normal;
  // Vertex maximising `score` among those passing `keep`; throws naming the landmark if none.
  int best(const std::string& name, const std::function<bool(int)>& keep, const std::function<double(int)>& score) const {
    int arg = -1;
    double top = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < v.rows(); ++i) {
      if (!keep(i)) continue;
      const double s = score(i);
      if (s > top) top = s, arg = i;
    }
    if (arg < 0) throw Error(ErrorKind::Format, "no vertex for landmark '" + name + "' (is this the hm08 mesh?)", name);
    return arg;
  }
  Vec p(int i) const { return v.row(i).transpose(); }
};

}  // namespace

std::map<std::string, int> pick_landmarks(const Assets& assets) {
  const Vertices apose = morph(assets, Shape{});
  const PosedBody ref = t_pose(assets, apose);
  const Vertices& v = ref.body;
  const Vertices n = vertex_normals(v, assets.mesh.body_faces);
  const Picker pk{v, n};
  const auto& mirror = assets.mesh.mirror;
  auto midline = [&](int i) { return mirror[static_cast<size_t>(i)] == i; };
  const auto& names = smpl_joint_names();
  auto joint = [&](const std::string& j) {
    const auto it = std::find(names.begin(), names.end(), j);
    return Vec(ref.joints.row(it - names.begin()).transpose());
  };
  // A joint cube the SMPL joints do not include (eyes, knuckles): the posed position of the body
  // vertex nearest the cube's centre in the A-pose.
  auto cube = [&](const std::string& group) {
    const auto it = assets.mesh.groups.find(group);
    if (it == assets.mesh.groups.end()) throw Error(ErrorKind::Format, "no joint cube '" + group + "'", group);
    Vec c = Vec::Zero();
    for (int i : it->second) c += apose.row(i).transpose();
    c /= static_cast<double>(it->second.size());
    int arg = 0;
    double d = std::numeric_limits<double>::infinity();
    for (int i = 0; i < kBodyVertexCount; ++i)
      if ((apose.row(i).transpose() - c).norm() < d) d = (apose.row(i).transpose() - c).norm(), arg = i;
    return pk.p(arg);
  };
  const double stature = v.col(1).maxCoeff();
  const double cm = 0.01;
  std::map<std::string, int> L;

  // Head. Vertex: the top; glabella: midline, most forward just above the eyes; opisthocranion:
  // midline, most backward above the eyes; head sides: widest above the ears.
  L["vertex"] = pk.best("vertex", midline, [&](int i) { return v(i, 1); });
  const double eye_y = cube("joint-r-eye")(1);
  L["glabella"] = pk.best("glabella", [&](int i) { return midline(i) && v(i, 1) > eye_y && v(i, 1) < eye_y + 2 * cm; },
                          [&](int i) { return v(i, 2); });
  L["opisthocranion"] = pk.best("opisthocranion", [&](int i) { return midline(i) && v(i, 1) > eye_y; },
                                [&](int i) { return -v(i, 2); });
  L["head_side_right"] = pk.best("head_side_right", [&](int i) { return v(i, 1) > eye_y + 2.5 * cm; }, [&](int i) { return -v(i, 0); });
  // Head circumference: a tape just above the brow ridges.
  L["head_circumference_front"] = pk.best("head_circumference_front",
      [&](int i) { return midline(i) && std::abs(v(i, 1) - (v(L["glabella"], 1) + 1.5 * cm)) < 0.6 * cm; },
      [&](int i) { return v(i, 2); });

  // Neck and spine.
  const Vec neck = joint("neck"), head = joint("head");
  L["cervicale"] = pk.best("cervicale", [&](int i) { return midline(i) && std::abs(v(i, 1) - neck(1)) < 1.5 * cm; },
                           [&](int i) { return -v(i, 2); });
  // Neck circumference: just above the neck joint, below the jaw (a section higher up catches the chin).
  const double neck_y = neck(1) + 0.1 * (head(1) - neck(1));
  L["neck_front"] = pk.best("neck_front", [&](int i) { return midline(i) && v(i, 2) > neck(2) && std::abs(v(i, 1) - neck_y) < 0.8 * cm; },
                            [&](int i) { return -std::abs(v(i, 1) - neck_y); });

  // Shoulders and arms (right side; T-pose, the arm along −X).
  const Vec shoulder = joint("right_shoulder"), elbow = joint("right_elbow"), wrist = joint("right_wrist");
  L["acromion_right"] = pk.best("acromion_right",
      [&](int i) { return v(i, 0) <= shoulder(0) + 2 * cm && v(i, 0) >= shoulder(0) && std::abs(v(i, 2) - shoulder(2)) < 3 * cm; },
      [&](int i) { return v(i, 1); });
  // Armpit: the highest point of the torso's side wall under the arm (normal facing outwards).
  L["axilla_right"] = pk.best("axilla_right",
      [&](int i) {
        return v(i, 0) > shoulder(0) && v(i, 0) < shoulder(0) + 8 * cm && std::abs(v(i, 2) - shoulder(2)) < 3 * cm &&
               v(i, 1) < shoulder(1) - 3 * cm && n(i, 0) < -0.8;
      },
      [&](int i) { return v(i, 1); });
  // The radial side of the forearm points from the wrist towards the thumb's base.
  Vec radial = cube("joint-r-finger-1-1") - wrist;
  radial -= radial.dot(Vec::UnitX()) * Vec::UnitX();
  radial.normalize();
  auto slab = [&](double x, double half) { return [&, x, half](int i) { return std::abs(v(i, 0) - x) < half && v(i, 0) < shoulder(0); }; };
  L["radiale_right"] = pk.best("radiale_right", slab(elbow(0), 0.8 * cm), [&](int i) { return (pk.p(i) - elbow).dot(radial); });
  L["stylion_right"] = pk.best("stylion_right", slab(wrist(0), 0.6 * cm), [&](int i) { return (pk.p(i) - wrist).dot(radial); });
  L["wrist_right"] = pk.best("wrist_right", slab(wrist(0), 0.6 * cm), [&](int i) { return v(i, 1); });
  L["biceps_right"] = pk.best("biceps_right", slab(0.5 * (shoulder(0) + elbow(0)), 0.8 * cm), [&](int i) { return v(i, 1); });
  L["forearm_right"] = pk.best("forearm_right", slab(elbow(0) + 0.25 * (wrist(0) - elbow(0)), 0.8 * cm), [&](int i) { return v(i, 1); });
  L["dactylion_right"] = pk.best("dactylion_right", [](int) { return true; }, [&](int i) { return -v(i, 0); });
  // Hand breadth at the knuckles: across the metacarpal heads of the index and little fingers,
  // the thumb (its own bones in the rig) left out.
  const int rthumb = assets.rig.bone_index("RThumb");
  auto thumb = [&](int i) {
    for (const auto& [b, w] : assets.rig.weights[static_cast<size_t>(i)])
      if (b == rthumb && w > 0.1f) return true;
    return false;
  };
  const double knuckle_x = 0.5 * (cube("joint-r-finger-2-1")(0) + cube("joint-r-finger-5-1")(0));
  auto knuckles = [&](int i) { return slab(knuckle_x, 0.6 * cm)(i) && !thumb(i); };
  L["metacarpal_right"] = pk.best("metacarpal_right", knuckles, [&](int i) { return (pk.p(i) - wrist).dot(radial); });
  L["metacarpal_ulnar_right"] = pk.best("metacarpal_ulnar_right", knuckles, [&](int i) { return -(pk.p(i) - wrist).dot(radial); });

  // Torso front: nipple = most forward chest point; chest_front on the midline at that height.
  L["thelion_right"] = pk.best("thelion_right",
      [&](int i) { return v(i, 0) < -3 * cm && v(i, 0) > -15 * cm && v(i, 1) < shoulder(1) - 5 * cm && v(i, 1) > shoulder(1) - 30 * cm; },
      [&](int i) { return v(i, 2); });
  const double nipple_y = v(L["thelion_right"], 1);
  L["chest_front"] = pk.best("chest_front", [&](int i) { return midline(i) && v(i, 2) > 0 && std::abs(v(i, 1) - nipple_y) < 1.0 * cm; },
                             [&](int i) { return -std::abs(v(i, 1) - nipple_y); });
  // Navel: the deepest dent of the front midline profile between the pelvis and the chest.
  const Vec pelvis = joint("pelvis"), hip = joint("right_hip"), knee = joint("right_knee"), ankle = joint("right_ankle");
  std::vector<int> front;
  for (int i = 0; i < kBodyVertexCount; ++i)
    if (midline(i) && n(i, 2) > 0.3 && v(i, 1) > pelvis(1) && v(i, 1) < nipple_y - 5 * cm) front.push_back(i);
  auto dent = [&](const std::vector<int>& profile, int i, double sign) {
    // How far i lies behind (sign +1: in front of) the mean of the profile 1.5–3 cm above and
    // below; both sides must be present, so the ends of the profile never count as dents.
    double s = 0;
    int above = 0, below = 0;
    for (int j : profile) {
      const double dy = v(j, 1) - v(i, 1);
      if (std::abs(dy) > 1.5 * cm && std::abs(dy) < 3 * cm) s += v(j, 2), ++(dy > 0 ? above : below);
    }
    return above && below ? sign * (s / (above + below) - v(i, 2)) : -1.0;
  };
  L["omphalion"] = pk.best("omphalion", [&](int i) { return std::find(front.begin(), front.end(), i) != front.end(); },
                           [&](int i) { return dent(front, i, 1); });
  // Crotch: the lowest midline vertex (the legs have none).
  L["crotch"] = pk.best("crotch", midline, [&](int i) { return -v(i, 1); });
  const double crotch_y = v(L["crotch"], 1);
  // Hips: iliac crest at the lower back joint's height, trochanterion at the hip joint's,
  // both the most lateral torso point there; hip breadth at the widest point below the navel.
  // (The T-posed arms and hands are far above these heights.)
  auto torso = [&](int i) { return v(i, 1) > crotch_y; };
  const double crest_y = joint("spine1")(1);
  L["iliocristale_right"] = pk.best("iliocristale_right", [&](int i) { return torso(i) && std::abs(v(i, 1) - crest_y) < 0.8 * cm; },
                                    [&](int i) { return -v(i, 0); });
  L["trochanterion_right"] = pk.best("trochanterion_right", [&](int i) { return torso(i) && std::abs(v(i, 1) - hip(1)) < 0.8 * cm; },
                                     [&](int i) { return -v(i, 0); });
  L["hip_left"] = pk.best("hip_left", [&](int i) { return torso(i) && v(i, 1) > crotch_y + 4 * cm && v(i, 1) < v(L["omphalion"], 1); },
                          [&](int i) { return v(i, 0); });
  L["buttock_back"] = pk.best("buttock_back", [&](int i) { return v(i, 0) < 0 && v(i, 1) > crotch_y - 5 * cm && v(i, 1) < pelvis(1) + 10 * cm; },
                              [&](int i) { return -v(i, 2); });
  // Gluteal furrow: the deepest dent of the back profile of the right buttock below its peak.
  const double bx = v(L["buttock_back"], 0);
  std::vector<int> back;
  for (int i = 0; i < kBodyVertexCount; ++i)
    if (std::abs(v(i, 0) - bx) < 1.5 * cm && n(i, 2) < -0.3 && v(i, 1) < v(L["buttock_back"], 1) && v(i, 1) > knee(1)) back.push_back(i);
  L["gluteal_furrow"] = pk.best("gluteal_furrow",
      [&](int i) { return std::find(back.begin(), back.end(), i) != back.end() && v(i, 1) > crotch_y - 12 * cm; },
      [&](int i) { return dent(back, i, -1); });

  // Right leg.
  auto right_leg = [&](int i) { return v(i, 0) < 0 && v(i, 1) < crotch_y; };
  const double thigh_y = v(L["gluteal_furrow"], 1);
  L["thigh_right"] = pk.best("thigh_right", [&](int i) { return right_leg(i) && std::abs(v(i, 1) - thigh_y) < 0.8 * cm; },
                             [&](int i) { return -v(i, 0); });
  const double lower_thigh_y = knee(1) + 0.2 * (hip(1) - knee(1));
  L["lower_thigh_right"] = pk.best("lower_thigh_right", [&](int i) { return right_leg(i) && std::abs(v(i, 1) - lower_thigh_y) < 0.8 * cm; },
                                   [&](int i) { return -v(i, 0); });
  L["knee_right"] = pk.best("knee_right", [&](int i) { return right_leg(i) && std::abs(v(i, 1) - knee(1)) < 2 * cm; },
                            [&](int i) { return v(i, 2); });
  L["calf_right"] = pk.best("calf_right",
      [&](int i) { return right_leg(i) && v(i, 1) < knee(1) - 5 * cm && v(i, 1) > ankle(1) + 10 * cm; },
      [&](int i) { return -v(i, 2); });
  const double ankle_y = ankle(1) + 4 * cm;
  L["ankle_right"] = pk.best("ankle_right", [&](int i) { return right_leg(i) && std::abs(v(i, 1) - ankle_y) < 0.8 * cm; },
                             [&](int i) { return -v(i, 0); });
  L["lateral_malleolus_right"] = pk.best("lateral_malleolus_right",
      [&](int i) { return right_leg(i) && std::abs(v(i, 1) - ankle(1)) < 2 * cm; }, [&](int i) { return -v(i, 0); });
  auto right_foot = [&](int i) { return v(i, 0) < 0 && v(i, 1) < ankle(1); };
  L["heel_right"] = pk.best("heel_right", right_foot, [&](int i) { return -v(i, 2); });
  L["toe_right"] = pk.best("toe_right", right_foot, [&](int i) { return v(i, 2); });
  auto forefoot = [&](int i) { return right_foot(i) && v(i, 2) > ankle(2) && v(i, 1) < ankle(1) - 2 * cm; };
  L["foot_medial_right"] = pk.best("foot_medial_right", forefoot, [&](int i) { return v(i, 0); });
  L["foot_lateral_right"] = pk.best("foot_lateral_right", forefoot, [&](int i) { return -v(i, 0); });

  // Left counterparts by the mesh's mirror map.
  for (const char* side : {"acromion", "thelion", "dactylion", "stylion", "wrist", "head_side"})
    L[std::string(side) + "_left"] = mirror[static_cast<size_t>(L.at(std::string(side) + "_right"))];
  (void)stature;
  return L;
}

std::vector<MeasurementDefinition> measurement_definitions() { return mannequin::measurement_definitions(); }

}  // namespace caliper::makehuman
