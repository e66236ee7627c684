// `caliper measure`, `caliper model`, `caliper isak`, `caliper map`.
#include <filesystem>
#include <thread>
#include <iomanip>
#include <iostream>
#include <regex>
#include <sstream>
#include <nlohmann/json.hpp>

#include "caliper/body/crease.h"
#include "caliper/evaluation/shape_count.h"
#include "caliper/export/uv_atlas.h"
#include "caliper/makehuman/builder.h"
#include "caliper/mannequin/population.h"
#include "common.h"

namespace caliper::cli {

namespace {

void print_measurements(const std::map<std::string, double>& values, bool json) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [name, v] : values) {
    const MeasurementInfo* info = find_measurement_info(name);
    const bool kg = info && info->unit == Unit::Kilogram;
    const double edge = kg ? v : v * 100;
    if (json) j[name + (kg ? "_kg" : "_cm")] = std::round(edge * 1000) / 1000;
    else std::cout << std::left << std::setw(28) << name << std::right << std::fixed << std::setprecision(2) << std::setw(9)
                   << edge << " " << (kg ? "kg" : "cm") << "\n";
  }
  if (json) std::cout << j.dump(2) << "\n";
}

}  // namespace

void register_measure(CLI::App& app) {
  auto opts = std::make_shared<BodyOptions>();
  auto mesh_file = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  CLI::App* cmd = app.add_subcommand("measure",
      "Measure a body: a model at given shape values (--beta) or measurements, or a closed OBJ mesh (--mesh)");
  add_body_options(*cmd, *opts, true);
  cmd->add_option("--mesh", *mesh_file,
                  "a closed OBJ mesh in metres: stature, volume and weight from volume (with --model's volume→weight fit)");
  cmd->add_flag("--json", *json, "print JSON instead of a table");
  cmd->callback([=] {
    if (!mesh_file->empty()) {
      Mesh m = read_obj(*mesh_file);
      // The same volume → weight fit the model's avatars use, so a mesh exported by `caliper
      // avatar` measures the weight its report gave.
      const BodyModel model = load_model(opts->model, parse_sex(opts->sex));
      const MeshMeasurements mm = measure_person_mesh(m, model.data().weight_from_volume, "--mesh");
      if (*json) {
        nlohmann::ordered_json j = {{"stature_cm", mm.stature * 100}, {"volume_l", mm.volume * 1000}, {"weight_kg", mm.weight}};
        std::cout << j.dump(2) << "\n";
      } else {
        std::cout << std::fixed << std::setprecision(2) << "stature  " << mm.stature * 100 << " cm\nvolume   "
                  << mm.volume * 1000 << " L\nweight   " << mm.weight << " kg (volume→weight fit of " << model.name()
                  << ")\n";
      }
      return;
    }
    if (opts->beta.empty() && opts->values.empty() && opts->extra.empty() && opts->measurements_file.empty())
      throw Error(ErrorKind::InvalidArgument,
                  "nothing to measure: give shape values (--beta 0 for the mean body), measurements (e.g. --height 170 "
                  "--weight 65, --measurements FILE) or a mesh (--mesh FILE.obj)", "measure");
    BuiltAvatar built = build_avatar(*opts);
    print_measurements(built.avatar.achieved, *json);
  });
}

namespace {

// Every ANSUR II CSV in a folder (sorted by name), or one CSV file; progress on stderr.
std::vector<AnsurSubject> read_ansur_folder(const std::string& path) {
  namespace fs = std::filesystem;
  std::vector<std::string> files;
  if (fs::is_directory(path)) {
    for (const auto& e : fs::directory_iterator(path))
      if (e.path().extension() == ".csv") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    if (files.empty()) throw Error(ErrorKind::Io, "no .csv files in '" + path + "'", "--ansur");
  } else {
    files.push_back(path);
  }
  std::vector<AnsurSubject> subjects;
  for (const auto& f : files) {
    auto part = read_ansur_csv(f);
    std::cerr << "read " << part.size() << " subjects from " << f << "\n";
    subjects.insert(subjects.end(), part.begin(), part.end());
  }
  return subjects;
}

// `caliper model choose-k`: the held-out validation curve behind the built-in models' K.
void register_choose_k(CLI::App& model) {
  auto ansur = std::make_shared<std::string>("../shared/data/ansur2");
  auto sex = std::make_shared<std::string>("female");
  auto counts = std::make_shared<std::vector<int>>(ShapeCountOptions{}.counts);
  auto folds = std::make_shared<int>(ShapeCountOptions{}.folds);
  auto json = std::make_shared<std::string>();
  CLI::App* cmd = model.add_subcommand(
      "choose-k", "Held-out validation of the number of shape directions K of the built-in body: per K, how well the "
                  "default estimator predicts unmeasured ANSUR columns of subjects left out of the model");
  cmd->add_option("--ansur", *ansur, "folder with ANSUR_II_{FEMALE,MALE}*.csv, or one CSV file")->capture_default_str();
  cmd->add_option("--sex", *sex, "female or male")->check(CLI::IsMember({"female", "male"}))->capture_default_str();
  cmd->add_option("--counts", *counts, "values of K to judge, comma separated (1–64)")->delimiter(',')->capture_default_str();
  cmd->add_option("--folds", *folds, "cross-validation folds (2–10): subject i is left out in fold i mod folds")
      ->capture_default_str();
  cmd->add_option("--json", *json, "also write the curve as JSON to this file");
  cmd->callback([=] {
    const std::vector<AnsurSubject> subjects = read_ansur_folder(*ansur);
    ShapeCountOptions opt;
    opt.counts = *counts;
    opt.folds = *folds;
    opt.threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    auto bars = std::make_shared<std::map<std::string, std::function<void(int, int)>>>();
    opt.progress = [bars](const std::string& stage, int done, int total) {
      auto it = bars->find(stage);
      if (it == bars->end()) it = bars->emplace(stage, progress_bar(stage)).first;
      it->second(done, total);
    };
    const auto curve = validate_shape_counts(subjects, parse_sex(*sex), opt);
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    std::cout << "| K | variance kept | held-out body RMS (mm) | mean held-out MAE (cm) | implausible |\n"
              << "|---|---|---|---|---|\n";
    for (const auto& p : curve) {
      std::cout << "| " << p.k << " | " << std::fixed << std::setprecision(2) << p.explained * 100 << " % | "
                << p.reconstruction_mm << " | " << std::setprecision(3) << p.mean_held_out_mae_cm << " | "
                << std::setprecision(1) << p.implausible_share * 100 << " % |\n";
      nlohmann::ordered_json cols;
      for (const auto& [col, mae] : p.held_out_mae) cols[col] = col == "weight" ? mae : mae * 100;
      out.push_back({{"k", p.k}, {"explained", p.explained}, {"reconstruction_mm", p.reconstruction_mm},
                     {"mean_held_out_mae_cm", p.mean_held_out_mae_cm}, {"implausible_share", p.implausible_share},
                     {"failures", p.failures}, {"held_out_mae_cm", cols}});
    }
    if (!json->empty()) {
      write_file(*json, out.dump(2) + "\n");
      std::cout << "wrote " << *json << "\n";
    }
  });
}

// `caliper model creases`: how sharply the surface folds, per body region (crease.h): over the
// built-in body's generated ANSUR population (--ansur), or on one model's mean body.
void print_crease_row(const std::string& region, double max_deg, const std::string& whose, double typical_deg, double p99_deg) {
  std::cout << "| " << region << " | " << std::fixed << std::setprecision(1) << max_deg << " | " << whose << " | "
            << typical_deg << " | " << p99_deg << " |\n";
}

void register_creases(CLI::App& model) {
  auto name = std::make_shared<std::string>("mannequin");
  auto sex = std::make_shared<std::string>("female");
  auto ansur = std::make_shared<std::string>();
  auto every = std::make_shared<int>(1);
  auto json = std::make_shared<std::string>();
  CLI::App* cmd = model.add_subcommand(
      "creases", "Creases: the largest dihedral angle between neighbouring faces per body region (torso, arms, legs "
                 "should be smooth; hands, feet and head carry intended features), on a model's mean body or, with "
                 "--ansur, on the built-in body generated for every ANSUR II subject of --sex");
  cmd->add_option("model", *name, "model name or .npz path (without --ansur)")->capture_default_str();
  cmd->add_option("--sex", *sex, "female, male or neutral")->capture_default_str();
  cmd->add_option("--ansur", *ansur, "folder with ANSUR_II_{FEMALE,MALE}*.csv, or one CSV file: survey the built-in body's population");
  cmd->add_option("--every", *every, "with --ansur: every N-th subject only (1–1000)")->check(CLI::Range(1, 1000))->capture_default_str();
  cmd->add_option("--json", *json, "also write the table as JSON to this file");
  cmd->callback([=] {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    double smooth_max = 0;
    std::cout << "| region | largest angle (°) | where | typical body's largest (°) | 99th percentile (°) |\n|---|---|---|---|---|\n";
    if (!ansur->empty()) {
      std::vector<AnsurSubject> all = read_ansur_folder(*ansur), picked;
      for (size_t i = 0; i < all.size(); i += static_cast<size_t>(*every)) picked.push_back(all[i]);
      const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
      const auto pop = mannequin::generate_population(picked, parse_sex(*sex), threads, progress_bar("generating bodies"));
      for (const auto& r : mannequin::survey_creases(pop, threads)) {
        print_crease_row(to_string(r.region), r.max_degrees, "subject " + r.worst_subject, r.median_body_max_degrees, r.max_p99_degrees);
        if (!is_feature_region(r.region)) smooth_max = std::max(smooth_max, r.max_degrees);
        out.push_back({{"region", to_string(r.region)}, {"max_degrees", r.max_degrees}, {"worst_subject", r.worst_subject},
                       {"worst_edge", {r.worst_edge.a, r.worst_edge.b}}, {"median_body_max_degrees", r.median_body_max_degrees},
                       {"max_p99_degrees", r.max_p99_degrees}});
      }
      std::cout << pop.bodies.rows() << " bodies; ";
    } else {
      const BodyModel m = load_model(*name, parse_sex(*sex));
      const auto report = crease_report(m, m.rest_vertices(Eigen::VectorXd()));
      for (const auto& r : report) {
        const std::string where = "edge " + std::to_string(r.worst.a) + "-" + std::to_string(r.worst.b);
        print_crease_row(to_string(r.region), r.max_degrees, where, r.max_degrees, r.p99_degrees);
        out.push_back({{"region", to_string(r.region)}, {"max_degrees", r.max_degrees}, {"worst_edge", {r.worst.a, r.worst.b}},
                       {"p99_degrees", r.p99_degrees}, {"edges", r.edges}});
      }
      smooth_max = smooth_region_max_crease(report);
      std::cout << m.name() << " mean body; ";
    }
    std::cout << "torso, arms and legs: largest angle " << std::setprecision(1) << smooth_max << "°\n";
    if (!json->empty()) {
      write_file(*json, out.dump(2) + "\n");
      std::cout << "wrote " << *json << "\n";
    }
  });
}

// `caliper model fidelity`: how closely the built-in body, generated for every ANSUR subject of
// --sex, reproduces their measurements (docs/mannequin.md "Fidelity over the development subset").
void register_fidelity(CLI::App& model) {
  auto sex = std::make_shared<std::string>("female");
  auto ansur = std::make_shared<std::string>();
  auto every = std::make_shared<int>(1);
  auto json = std::make_shared<std::string>();
  CLI::App* cmd = model.add_subcommand(
      "fidelity", "Fidelity: the built-in body generated for every ANSUR II subject of --sex, measured with Caliper's "
                  "own definitions against the subject's values: mean error (bias), largest error and bodies out of "
                  "tolerance (3 mm; 1 % for circumferences) per target");
  cmd->add_option("--ansur", *ansur, "folder with ANSUR_II_{FEMALE,MALE}*.csv, or one CSV file")->required();
  cmd->add_option("--sex", *sex, "female or male")->check(CLI::IsMember({"female", "male"}))->capture_default_str();
  cmd->add_option("--every", *every, "every N-th subject only (1–1000)")->check(CLI::Range(1, 1000))->capture_default_str();
  cmd->add_option("--json", *json, "also write the table as JSON to this file");
  cmd->callback([=] {
    std::vector<AnsurSubject> all = read_ansur_folder(*ansur), picked;
    for (size_t i = 0; i < all.size(); i += static_cast<size_t>(*every)) picked.push_back(all[i]);
    const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    const auto pop = mannequin::generate_population(picked, parse_sex(*sex), threads, progress_bar("generating bodies"));
    if (pop.bodies.rows() == 0) throw Error(ErrorKind::Format, "no " + *sex + " subjects in " + *ansur, "ansur");
    const auto rows = mannequin::survey_fidelity(pop, threads);
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    std::cout << "| measurement | mean error (cm) | largest error | out of tolerance | worst subject |\n|---|---|---|---|---|\n";
    int missed_targets = 0;
    for (const auto& r : rows) {
      std::ostringstream largest;
      largest << std::fixed << std::setprecision(2) << r.max_abs_error_m * 1000 << " mm";
      if (r.target.circumference) largest << " (" << std::setprecision(3) << r.max_abs_error_fraction * 100 << " %)";
      std::cout << "| " << r.target.measurement << " | " << std::showpos
                << std::fixed << std::setprecision(2) << r.mean_error_m * 100 << std::noshowpos << " | " << largest.str()
                << " | " << r.out_of_tolerance << " of " << r.bodies << " | " << r.worst_subject << " |\n";
      if (r.out_of_tolerance > 0) ++missed_targets;
      out.push_back({{"measurement", r.target.measurement}, {"ansur_column", r.target.ansur_column},
                     {"mean_error_cm", r.mean_error_m * 100}, {"max_abs_error_mm", r.max_abs_error_m * 1000},
                     {"max_abs_error_percent", r.max_abs_error_fraction * 100}, {"out_of_tolerance", r.out_of_tolerance},
                     {"bodies", r.bodies}, {"worst_subject", r.worst_subject}});
    }
    std::cout << pop.bodies.rows() << " bodies; " << rows.size() - static_cast<size_t>(missed_targets) << " of "
              << rows.size() << " targets within tolerance on every body\n";
    if (!json->empty()) {
      write_file(*json, out.dump(2) + "\n");
      std::cout << "wrote " << *json << "\n";
    }
  });
}

}  // namespace

namespace {

// Rounds a JSON document's numbers to 4 decimals (a fit's offset of -2.430762547713041 cm reads
// -2.4308), recursively.
void round_numbers(nlohmann::ordered_json& j) {
  if (j.is_number_float()) j = std::round(j.get<double>() * 1e4) / 1e4 + 0.0;  // + 0.0: no "-0.0"
  if (j.is_structured())  // (iterating a number would visit the number itself)
    for (auto& item : j) round_numbers(item);
}

// Model metadata as people read it: JSON with its numbers rounded, and in plain text the
// round-off residue of a fit (-8.35202e-14) written as the 0 it is.
std::string tidy_numbers(const std::string& text) {
  if (!text.empty() && text[0] == '{') {
    auto j = nlohmann::ordered_json::parse(text, nullptr, false);
    if (!j.is_discarded()) {
      round_numbers(j);
      return j.dump(2);
    }
  }
  static const std::regex scientific(R"([-+]?[0-9]+(\.[0-9]+)?[eE][-+]?[0-9]+)");
  std::string out;
  auto begin = std::sregex_iterator(text.begin(), text.end(), scientific);
  size_t last = 0;
  for (auto it = begin; it != std::sregex_iterator(); ++it) {
    out += text.substr(last, static_cast<size_t>(it->position()) - last);
    const double v = std::strtod(it->str().c_str(), nullptr);
    out += std::abs(v) < 1e-6 ? "0" : it->str();
    last = static_cast<size_t>(it->position() + it->length());
  }
  return out + text.substr(last);
}

}  // namespace

void register_model(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("model", "Inspect body models");
  cmd->require_subcommand(1);
  auto name = std::make_shared<std::string>("mannequin");
  auto sex = std::make_shared<std::string>("female");
  auto json = std::make_shared<bool>(false);
  CLI::App* info = cmd->add_subcommand("info", "Vertex, face, joint and shape-direction counts, landmarks, measurements");
  info->add_option("model", *name, "model name or .npz path (native or SMPL)")->capture_default_str();
  info->add_option("--sex", *sex, "variant of a model family")->capture_default_str();
  info->add_flag("--json", *json, "print JSON");
  info->callback([=] {
    const BodyModel m = load_model(*name, parse_sex(*sex));
    const auto& d = m.data();
    nlohmann::ordered_json j;
    j["name"] = m.name();
    j["sex"] = to_string(m.sex());
    j["vertices"] = m.vertex_count();
    j["faces"] = m.face_count();
    j["joints"] = m.joint_count();
    j["shape_directions"] = m.shape_count();
    j["joint_names"] = d.joint_names;
    j["weight_from_volume"] = {{"a", d.weight_from_volume.a}, {"b", d.weight_from_volume.b}};
    j["landmarks"] = nlohmann::ordered_json::object();
    for (const auto& [l, v] : d.landmarks) j["landmarks"][l] = v;
    j["measurements"] = nlohmann::ordered_json::array();
    for (const auto& md : d.measurements) j["measurements"].push_back(md.name);
    j["metadata"] = d.metadata;
    if (*json) { std::cout << j.dump(2) << "\n"; return; }
    std::cout << "model             " << m.name() << " (" << to_string(m.sex()) << ")\n"
              << "vertices          " << m.vertex_count() << "\nfaces             " << m.face_count()
              << "\njoints            " << m.joint_count() << "\nshape directions  " << m.shape_count()
              << "\nweight = " << d.weight_from_volume.a << " · volume + " << d.weight_from_volume.b << "\nlandmarks (" << d.landmarks.size() << ")  ";
    for (const auto& [l, v] : d.landmarks) std::cout << l << " ";
    std::cout << "\nmeasurements (" << d.measurements.size() << ")  ";
    for (const auto& md : d.measurements) std::cout << md.name << " ";
    std::cout << "\n";
    for (const auto& [k, v] : d.metadata) std::cout << k << ": " << tidy_numbers(v) << "\n";
  });
  auto ansur = std::make_shared<std::string>("../shared/data/ansur2");
  auto out = std::make_shared<std::string>();
  auto components = std::make_shared<int>(0);  // 0: the kind's own default
  auto build_sex = std::make_shared<std::string>("female");
  auto assets = std::make_shared<std::string>();
  auto max_subjects = std::make_shared<int>(makehuman::BuildOptions{}.max_subjects);
  CLI::App* build = cmd->add_subcommand("build", "Build a body model from data (kind: mannequin or makehuman)");
  auto kind = std::make_shared<std::string>();
  build->add_option("kind", *kind,
                    "mannequin: Caliper's own body, one generated body per ANSUR II subject, then PCA; "
                    "makehuman: MakeHuman's CC0 body fitted to each ANSUR II subject, then PCA (needs --assets)")
      ->required()->check(CLI::IsMember({"mannequin", "makehuman"}));
  build->add_option("--assets", *assets, "makehuman: folder of MakeHuman assets in MPFB2 layout (e.g. ../shared/data/makehuman)");
  build->add_option("--subjects", *max_subjects,
                    "makehuman: subjects fitted, evenly subsampled from the file (0 = all; fitting costs ~0.1 s per subject and core)")
      ->capture_default_str();
  build->add_option("--ansur", *ansur, "folder with ANSUR_II_{FEMALE,MALE}*.csv, or one CSV file")->capture_default_str();
  build->add_option("--sex", *build_sex, "female, male or neutral (both sexes)")->capture_default_str();
  build->add_option("--components", *components,
                    "shape directions kept, K (1–64); default: mannequin " +
                        std::to_string(mannequin::PopulationOptions{}.components) +
                        " (chosen by held-out validation, `caliper model choose-k`), makehuman " +
                        std::to_string(makehuman::BuildOptions{}.components));
  build->add_option("-o,--output", *out, "model file to write (.npz)")->required();
  build->callback([=] {
    (void)kind;  // bound to the positional argument; kept alive by this capture
    const Sex model_sex = parse_sex(*build_sex);
    if (*kind == "makehuman" && assets->empty())
      throw Error(ErrorKind::InvalidArgument, "makehuman needs --assets DIR (a MakeHuman assets folder)", "--assets");
    namespace fs = std::filesystem;
    // Checked before the (slower) ANSUR read, so a wrong folder is reported at once.
    if (*kind == "makehuman" && !fs::is_directory(*assets))
      throw Error(ErrorKind::Io, "--assets '" + *assets + "' is not a folder (MakeHuman assets in MPFB2 layout)", "--assets");
    const std::vector<AnsurSubject> subjects = read_ansur_folder(*ansur);
    if (*kind == "makehuman") {
      std::cerr << "reading MakeHuman assets from " << *assets << "\n";
      const makehuman::Assets mh = makehuman::load_assets(*assets);
      for (const auto& p : mh.problems) std::cerr << "warning: target " << p.name << ": " << p.reason << "\n";
      makehuman::BuildOptions mo;
      if (*components) mo.components = *components;
      mo.max_subjects = *max_subjects;
      mo.threads = std::max(1u, std::thread::hardware_concurrency());
      mo.progress = progress_bar("fitting subjects");
      makehuman::BuildReport rep;
      BodyModel model = makehuman::build_makehuman_model(mh, subjects, model_sex, mo, &rep);
      save_model(model, *out);
      std::cout << "built " << model.name() << " from " << rep.subjects << " of " << rep.subjects_available
                << " subjects: " << model.vertex_count() << " vertices, K = " << model.shape_count() << " ("
                << std::fixed << std::setprecision(1) << rep.total_explained * 100 << " % of shape variance)\n"
                << std::setprecision(2) << "weight from volume: fitted a = " << rep.fitted.a << ", b = " << rep.fitted.b
                << " (MAE " << rep.weight_mae_fitted_kg << " kg); paper's CAESAR coefficients: MAE "
                << rep.weight_mae_paper_kg << " kg, bias " << rep.weight_bias_paper_kg << " kg\n"
                << "fit, mean |achieved - ANSUR|:";
      for (const auto& [measurement, v] : rep.fit_mae)
        std::cout << " " << measurement << " " << (measurement == "weight" ? v : v * 100) << (measurement == "weight" ? " kg;" : " cm;");
      std::cout << "\njoint regressor vs the rig's joints: RMS " << rep.joint_rms_m * 1000 << " mm\n";
      if (!rep.failed_subjects.empty())
        std::cout << rep.failed_subjects.size() << " subjects could not be fitted (first: " << rep.failed_subjects.front() << ")\n";
      std::cout << "wrote " << *out << "\n";
      return;
    }
    mannequin::PopulationOptions po;
    if (*components) po.components = *components;
    po.threads = std::max(1u, std::thread::hardware_concurrency());
    po.progress = progress_bar("generating bodies");
    mannequin::PopulationReport rep;
    BodyModel model = mannequin::build_mannequin_model(subjects, model_sex, po, &rep);
    save_model(model, *out);
    std::cout << "built " << model.name() << " from " << rep.subjects << " subjects: " << model.vertex_count()
              << " vertices, K = " << model.shape_count() << " (" << std::fixed << std::setprecision(1)
              << rep.total_explained * 100 << " % of shape variance)\n"
              << std::setprecision(2) << "weight from volume: fitted a = " << rep.fitted.a << ", b = " << rep.fitted.b
              << " (MAE " << rep.weight_mae_fitted_kg << " kg); paper's CAESAR coefficients: MAE "
              << rep.weight_mae_paper_kg << " kg, bias " << rep.weight_bias_paper_kg << " kg\n"
              << "wrote " << *out << "\n";
  });
  register_choose_k(*cmd);
  register_creases(*cmd);
  register_fidelity(*cmd);
  auto atlas_name = std::make_shared<std::string>("mannequin");
  auto atlas_sex = std::make_shared<std::string>("female");
  auto atlas_out = std::make_shared<std::string>();
  auto atlas_size = std::make_shared<int>(UvAtlasOptions{}.size);
  CLI::App* atlas = cmd->add_subcommand("uv-atlas", "Draw a model's UV layout (texture coordinates) as a PNG");
  atlas->add_option("model", *atlas_name, "model name or .npz path")->capture_default_str();
  atlas->add_option("--sex", *atlas_sex, "variant of a model family")->capture_default_str();
  atlas->add_option("--size", *atlas_size, "image width and height, pixels (16–8192)")->capture_default_str();
  atlas->add_option("-o,--output", *atlas_out, "PNG file to write")->required();
  atlas->callback([=] {
    const BodyModel m = load_model(*atlas_name, parse_sex(*atlas_sex));
    if (!m.has_uvs()) throw Error(ErrorKind::Unsupported, "model '" + m.name() + "' has no UV layout", "model");
    UvAtlasOptions ao;
    ao.size = *atlas_size;
    write_file(*atlas_out, render_uv_atlas_png(m.data().uv_coordinates, m.data().uv_faces, ao));
    std::cout << "wrote " << *atlas_out << " (" << m.data().uv_coordinates.rows() << " UVs for "
              << m.vertex_count() << " vertices)\n";
  });
  CLI::App* list = cmd->add_subcommand("list", "List the models in the models folder");
  list->callback([] {
    const std::string dir = models_dir();
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(dir, ec))
      if (e.path().extension() == ".npz") names.push_back(e.path().stem().string());
    std::sort(names.begin(), names.end());
    std::cout << "models in " << dir << ":\n";
    for (const auto& n : names) std::cout << "  " << n << "\n";
  });
}

void register_isak(CLI::App& app) {
  auto values = std::make_shared<std::vector<double>>();
  CLI::App* cmd = app.add_subcommand("isak",
      "Combine repeated measurements by the ISAK rule: two within 1.5 % → their mean, else the median of three");
  // At least one value for CLI11, so its help shows no "x 2"; two or three are checked here.
  cmd->add_option("values", *values, "2 or 3 repetitions of one measurement (any unit), e.g. 171.2 170.4")
      ->required()
      ->expected(1, 3)
      ->type_name("VALUE VALUE [VALUE]");
  cmd->callback([=] {
    if (values->size() < 2)
      throw CLI::ValidationError("values", "the ISAK rule needs 2 or 3 repetitions of one measurement, got 1");
    IsakResult r = isak_combine(*values);
    std::cout << std::fixed << std::setprecision(3) << "difference of the first two: " << r.relative_difference * 100 << " %\n";
    if (r.value) std::cout << "rule: " << to_string(r.rule) << "\nvalue: " << *r.value << "\n";
    else {
      std::cout << "rule: need_third (they differ by 1.5 % or more: take a third measurement)\n";
    }
  });
}

void register_map(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("map", "Real → virtual measurement maps (paper §3.3)");
  cmd->require_subcommand(1);
  auto csv = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  CLI::App* fit = cmd->add_subcommand("fit", "Fit one linear map per measurement from a CSV: measurement,real_cm,virtual_cm");
  fit->add_option("pairs", *csv, "CSV of paired values")->required();
  fit->add_option("-o,--output", *out, "map file to write (JSON)")->required();
  fit->callback([=] {
    RealToVirtual r = RealToVirtual::fit_csv(*csv);
    r.save(*out);
    for (const auto& [name, m] : r.maps())
      std::cout << name << ": virtual = " << m.slope << " · real + " << m.offset * 100 << " cm  (" << m.pairs
                << " pairs, rmse " << m.rmse * 100 << " cm)\n";
    std::cout << "wrote " << *out << "\n";
  });
}

}  // namespace caliper::cli
