// `caliper avatar` and `caliper render`: build an avatar from measurements and write it out.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "caliper/export/render.h"
#include "common.h"

namespace caliper::cli {

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  std::string tail = s.substr(s.size() - suffix.size());
  for (auto& c : tail) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return tail == suffix;
}

void print_summary(const BuiltAvatar& built, std::ostream& os) {
  const Avatar& a = built.avatar;
  const Plausibility& p = a.plausibility;
  os << "model " << built.model->name() << ", regressor " << a.regressor << "\n"
     << "verdict: " << to_string(p.overall) << ", " << p.rarity << " (" << p.population << ")\n";
  for (const auto& d : p.drivers) os << "  because " << d << "\n";
  // A value in the catalogue's edge unit (cm or kg) and that unit's name.
  auto edge = [](const std::string& name, double si) -> std::pair<double, std::string> {
    const MeasurementInfo* info = find_measurement_info(name);
    return info ? std::pair{si_to_edge(*info, si), std::string(edge_unit(*info))} : std::pair{si * 100, std::string("cm")};
  };
  const bool sd = !a.uncertainty.empty();
  os << std::left << std::setw(26) << "measurement" << std::right << std::setw(12) << "requested" << std::setw(12)
     << "achieved" << std::setw(10) << "Δ" << (sd ? "     ± SD" : "") << "\n";
  std::vector<std::string> rest_pose_notes;  // Δ's header above is two bytes wide, one column
  for (const auto& [name, rest_pose] : a.achieved) {
    // Values as a person measures them, so Δ compares like with like (report: docs/cli.md).
    const double achieved = as_measured(a, name, rest_pose);
    const auto [value, unit] = edge(name, achieved);
    os << std::left << std::setw(26) << name << std::right << std::fixed << std::setprecision(2);
    auto req = a.requested.find(name);
    if (req != a.requested.end()) os << std::setw(9) << edge(name, req->second).first << " " << unit;
    else os << std::setw(12) << "";
    os << std::setw(9) << value << " " << unit;
    if (req != a.requested.end()) {
      const double delta = value - edge(name, req->second).first;
      os << std::showpos << std::setw(9) << (std::abs(delta) < 0.005 ? 0.0 : delta) << std::noshowpos;  // no "-0.00"
    }
    else os << std::setw(9) << "";
    if (auto u = a.uncertainty.find(name); u != a.uncertainty.end())
      os << std::setw(9) << edge(name, sd_as_measured(a, name, u->second)).first;
    os << "\n";
    if (measured_differs_from_rest_pose(a, name)) {
      std::ostringstream note;
      note << std::fixed << std::setprecision(2) << name << " is given as a person measures it; in its T-pose rest pose "
           << "the avatar's is " << edge(name, rest_pose).first << " " << unit;
      rest_pose_notes.push_back(note.str());
    }
  }
  for (const auto& n : rest_pose_notes) os << "note: " << n << " (docs/cli.md, \"Arm length\")\n";
}

}  // namespace

void register_avatar(CLI::App& app) {
  auto opts = std::make_shared<BodyOptions>();
  auto output = std::make_shared<std::string>();
  auto report = std::make_shared<std::string>();
  auto quiet = std::make_shared<bool>(false);
  auto skeleton = std::make_shared<std::string>("smpl");
  auto morphs = std::make_shared<bool>(false);
  CLI::App* cmd = app.add_subcommand("avatar", "Build a rigged avatar from measurements and export it (.glb, .vrm, .fbx or .obj)");
  add_body_options(*cmd, *opts, true);
  cmd->add_option("-o,--output", *output, "output file: avatar.glb (rigged glTF 2.0 binary), avatar.vrm (VRM 1.0 humanoid), avatar.fbx (rigged FBX 7.4 binary) or avatar.obj")->required();
  cmd->add_option("--skeleton", *skeleton,
                  "bone names: smpl (the model's, default; SMPL pose data drives them) or humanoid (Unity Humanoid names)");
  cmd->add_option("--report", *report, "also write a JSON report (requested vs achieved measurements, shape, plausibility)");
  cmd->add_flag("--morphs", *morphs, ".glb / .vrm / .fbx: also write the model's shape directions as morph targets (blend shapes)");
  cmd->add_flag("-q,--quiet", *quiet, "do not print the measurement table");
  cmd->callback([=] {
    const AvatarFormat format = avatar_file_format(*output, "--output");
    // Both files' folders are checked first, so a bad --report does not leave a lone mesh behind.
    for (const auto& [path, option] : {std::pair{*output, "--output"}, std::pair{*report, "--report"}}) {
      const auto folder = std::filesystem::path(path).parent_path();
      std::error_code ec;
      if (!path.empty() && !folder.empty() && !std::filesystem::is_directory(folder, ec))
        throw Error(ErrorKind::Io, std::string(option) + ": there is no folder '" + folder.string() + "'", option);
    }
    AvatarFileOptions file;
    file.skeleton = parse_skeleton_naming(*skeleton, "--skeleton");
    file.morphs = *morphs;
    check_avatar_file_options(format, file, "--morphs");  // before the build, so a refusal costs nothing
    BuiltAvatar built = build_avatar(*opts);
    save_avatar(*output, *built.model, built.avatar, "--output", file);
    if (!report->empty()) write_file(*report, avatar_report_json(*built.model, built.avatar));
    if (!*quiet) print_summary(built, std::cout);
    std::cout << "wrote " << *output << (report->empty() ? "" : " and " + *report) << "\n";
  });
}

// Frames a close-up of the part of `shown` (posed vertices) that joint `name` moves: the vertices
// whose largest skinning weight is that joint, centred on their bounding box, radius their
// bounding sphere (at least 5 cm) unless `radius` (metres) > 0.
void frame_joint(const BodyModel& model, const Vertices& shown, const std::string& name, double radius,
                 RenderOptions& ro) {
  const auto& names = model.data().joint_names;
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) {
    std::string known;
    for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
    throw Error(ErrorKind::InvalidArgument, "--focus: model '" + model.name() + "' has no joint '" + name + "' (" + known + ")",
                "--focus");
  }
  const int joint = static_cast<int>(it - names.begin());
  const auto& w = model.data().skin_weights;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  int count = 0;
  for (Eigen::Index v = 0; v < w.rows(); ++v) {
    int best = -1;
    double best_w = -1;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator e(w, v); e; ++e)
      if (e.value() > best_w) { best_w = e.value(); best = static_cast<int>(e.col()); }
    if (best != joint) continue;
    lo = lo.cwiseMin(shown.row(v).transpose());
    hi = hi.cwiseMax(shown.row(v).transpose());
    ++count;
  }
  if (count == 0) throw Error(ErrorKind::InvalidArgument, "--focus: joint '" + name + "' moves no vertex most", "--focus");
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  for (int c = 0; c < 3; ++c) ro.focus_center[static_cast<size_t>(c)] = centre(c);
  ro.focus_radius = radius > 0 ? radius : std::max(0.05, 0.5 * (hi - lo).norm());
}

void register_render(CLI::App& app) {
  auto opts = std::make_shared<BodyOptions>();
  auto output = std::make_shared<std::string>();
  auto views = std::make_shared<std::vector<std::string>>(std::vector<std::string>{"front", "side", "back", "three-quarter"});
  auto width = std::make_shared<int>(480);
  auto height = std::make_shared<int>(800);
  auto mesh_file = std::make_shared<std::string>();
  auto pose = std::make_shared<std::string>("t");
  auto pose_file = std::make_shared<std::string>();
  auto heat = std::make_shared<bool>(false);
  auto checker = std::make_shared<bool>(false);
  auto focus = std::make_shared<std::string>();
  auto focus_radius_cm = std::make_shared<double>(0.0);
  CLI::App* cmd = app.add_subcommand("render", "Render an avatar (or an OBJ mesh) to a PNG picture, several views side by side");
  add_body_options(*cmd, *opts, true);
  cmd->add_option("--mesh", *mesh_file, "render this OBJ file instead of building an avatar");
  cmd->add_option("-o,--output", *output, "output PNG file (.png)")->required();
  cmd->add_option("--views", *views, "views: front, side, back, three-quarter, top (from above, the body's front at the bottom)")->delimiter(',')->capture_default_str();
  CLI::Option* pose_option = cmd->add_option("--pose", *pose,
                  "t (rest pose, arms horizontal), a (arms lowered 45°), stride (mid-stride, knees and elbows bent) or "
                  "fist (arms lowered 45°, hands closed); a, stride and fist are posed by the rig's skinning")
      ->check(CLI::IsMember({"t", "a", "stride", "fist"}))
      ->capture_default_str();
  cmd->add_option("--pose-file", *pose_file,
                  "pose the body with SMPL-family axis-angle values (radians) from a JSON file instead of --pose: an "
                  "array (or {\"pose\": array}) of 72 numbers (SMPL), 156 (SMPL-H, with fingers) or 162 (Caliper's "
                  "rig), or of [x, y, z] triples; see docs/cli.md")
      ->excludes(pose_option);
  cmd->add_flag("--uncertainty", *heat,
                "colour the body by the per-vertex SD of --regressor map (blue: certain, red: the body's largest SD)");
  cmd->add_flag("--uv-checker", *checker,
                "paint the body with a checker texture through the model's UV layout (or the OBJ's texture coordinates)");
  cmd->add_option("--focus", *focus,
                  "close-up of the body part a joint moves, by the model's joint name (head, neck, left_wrist, "
                  "right_knee, ...): framed on the vertices that joint moves most, in the pose drawn");
  cmd->add_option("--focus-radius", *focus_radius_cm,
                  "with --focus: radius of the framed sphere, cm (default: the part's own size, e.g. the head's)");
  cmd->add_option("--image-width", *width, "width of each view in pixels (64–4096)")->capture_default_str();
  cmd->add_option("--image-height", *height, "height of each view in pixels (64–4096)")->capture_default_str();
  cmd->callback([=] {
    if (!ends_with(*output, ".png"))
      throw Error(ErrorKind::InvalidArgument, "--output must end in .png (the picture is a PNG), got '" + *output + "'", "--output");
    if (*width < 64 || *width > 4096) throw Error(ErrorKind::OutOfRange, "--image-width must be in [64, 4096]", "--image-width");
    if (*height < 64 || *height > 4096) throw Error(ErrorKind::OutOfRange, "--image-height must be in [64, 4096]", "--image-height");
    std::vector<View> vs;
    for (const auto& v : *views) {
      if (v == "front") vs.push_back(View::Front);
      else if (v == "side") vs.push_back(View::Side);
      else if (v == "back") vs.push_back(View::Back);
      else if (v == "three-quarter" || v == "3/4" || v == "threequarter") vs.push_back(View::ThreeQuarter);
      else if (v == "top") vs.push_back(View::Top);
      else throw Error(ErrorKind::InvalidArgument, "unknown view '" + v + "' (front, side, back, three-quarter, top)", "--views");
    }
    RenderOptions ro;
    ro.width = *width;
    ro.height = *height;
    if (!(std::isfinite(*focus_radius_cm) && *focus_radius_cm >= 0 && *focus_radius_cm <= 500))
      throw Error(ErrorKind::OutOfRange, "--focus-radius must be in [0, 500] cm", "--focus-radius");
    if (*focus_radius_cm > 0 && focus->empty())
      throw Error(ErrorKind::InvalidArgument, "--focus-radius needs --focus JOINT", "--focus-radius");
    if (!mesh_file->empty()) {
      // The file is drawn as it is: options that shape or pose an avatar would be ignored.
      if (!focus->empty())
        throw Error(ErrorKind::InvalidArgument, "--focus needs a model's joints; an OBJ file has none", "--focus");
      if (*pose != "t" || *heat || !opts->values.empty() || !opts->extra.empty() || !opts->beta.empty() ||
          !opts->measurements_file.empty())
        throw Error(ErrorKind::InvalidArgument,
                    "--mesh draws the file as it is: --pose, --uncertainty, measurements and --beta do not apply to it",
                    "--mesh");
      TexturedMesh m = read_obj_textured(*mesh_file);
      if (*checker) {
        if (m.uv_faces.rows() == 0)
          throw Error(ErrorKind::Unsupported, "--uv-checker: '" + *mesh_file + "' has no texture coordinates", "--uv-checker");
        ro.uv_coordinates = m.uv_coordinates;
        ro.uv_faces = m.uv_faces;
      }
      write_file(*output, render_views_png(m.mesh.vertices, m.mesh.faces, vs, ro));
    } else {
      BuiltAvatar built = build_avatar(*opts);
      if (*heat) {
        const Eigen::VectorXd& sd = built.avatar.vertex_sd;
        if (sd.size() == 0)
          throw Error(ErrorKind::InvalidArgument, "--uncertainty needs --regressor map (only map estimates it)", "--uncertainty");
        ro.vertex_scalar.assign(sd.data(), sd.data() + sd.size());
        ro.scalar_min = 0.0f;
        ro.scalar_max = static_cast<float>(sd.maxCoeff());
      }
      const BodyModel& model = *built.model;
      if (*checker) {
        if (!model.has_uvs())
          throw Error(ErrorKind::Unsupported, "--uv-checker: model '" + model.name() + "' has no UV layout", "--uv-checker");
        ro.uv_coordinates = model.data().uv_coordinates;
        ro.uv_faces = model.data().uv_faces;
      }
      const Vertices& rest = built.avatar.rest_vertices;
      const Vertices shown = !pose_file->empty()  ? pose_vertices(model, rest, load_pose(model, *pose_file))
                             : *pose == "a"        ? pose_vertices(model, rest, a_pose(model))
                             : *pose == "stride" ? pose_vertices(model, rest, stride_pose(model))
                             : *pose == "fist"   ? pose_vertices(model, rest, a_pose(model) + fist_pose(model))
                                                 : rest;
      if (!focus->empty()) frame_joint(model, shown, *focus, *focus_radius_cm / 100.0, ro);
      write_file(*output, render_views_png(shown, built.model->faces(), vs, ro));
    }
    std::cout << "wrote " << *output << "\n";
  });
}

}  // namespace caliper::cli
