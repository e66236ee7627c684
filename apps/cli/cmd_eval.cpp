// `caliper eval` and `caliper batch`: avatars for every row of an ANSUR II-format CSV.
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <thread>
#include <nlohmann/json.hpp>

#include "caliper/evaluation/evaluate.h"
#include "caliper/io/ansur.h"
#include "common.h"

namespace caliper::cli {

namespace {

struct SubjectsOptions {
  std::string subjects;
  std::string model = "mannequin";
};

std::function<std::shared_ptr<const AvatarBuilder>(Sex)> builders_for(const std::string& model) {
  auto cache = std::make_shared<std::map<Sex, std::shared_ptr<const AvatarBuilder>>>();
  return [cache, model](Sex sex) {
    auto& b = (*cache)[sex];
    if (!b) b = std::make_shared<const AvatarBuilder>(std::make_shared<const BodyModel>(load_model(model, sex)));
    return b;
  };
}

void print_table(const std::string& title, const std::map<std::string, MethodEvaluation>& methods) {
  for (const auto& [name, me] : methods) {
    std::cout << "\n" << title << " " << name << ": implausible " << std::fixed << std::setprecision(1)
              << me.implausible_share * 100 << " %" << (me.failures ? ", " + std::to_string(me.failures) + " failed" : "")
              << "\n  inputs (avatar − input)      MAE      max\n";
    for (const auto& [k, s] : me.inputs) {
      const bool kg = k == "weight";
      std::cout << "    " << std::left << std::setw(24) << k << std::right << std::setprecision(2) << std::setw(7)
                << s.mae * (kg ? 1 : 100) << std::setw(9) << s.max * (kg ? 1 : 100) << (kg ? " kg" : " cm") << "\n";
    }
    std::cout << "  held out (avatar − measured)  MAE     bias    linear limit  ratio\n";
    for (const auto& [k, s] : me.held_out) {
      const bool kg = k == "weight";
      std::cout << "    " << std::left << std::setw(24) << k << std::right << std::setprecision(2) << std::setw(7)
                << s.mae * (kg ? 1 : 100) << std::setw(9) << s.bias * (kg ? 1 : 100) << (kg ? " kg" : " cm");
      if (auto l = me.linear_limit.find(k); l != me.linear_limit.end())
        std::cout << std::setw(9) << l->second.mae * 100 << " cm" << std::setw(7) << me.ratio_to_linear.at(k);
      std::cout << "\n";
    }
    if (!me.ratio_to_linear.empty())
      std::cout << "  held out / linear limit: median " << std::setprecision(3) << me.ratio_median << ", worst "
                << me.ratio_worst << " (" << me.ratio_worst_column << ")\n";
    if (!me.calibration.empty()) {
      std::cout << "  calibration (truth within)    ±1 SD    ±2 SD  mean SD\n";
      for (const auto& [k, c] : me.calibration) {
        const bool kg = k == "weight";
        std::cout << "    " << std::left << std::setw(24) << k << std::right << std::setprecision(1) << std::setw(7)
                  << c.within_1sd * 100 << " %" << std::setw(7) << c.within_2sd * 100 << " %" << std::setprecision(2)
                  << std::setw(7) << c.mean_sd * (kg ? 1 : 100) << (kg ? " kg" : " cm") << "\n";
      }
    }
  }
}

}  // namespace

void register_eval(CLI::App& app) {
  auto o = std::make_shared<SubjectsOptions>();
  auto regressors = std::make_shared<std::vector<std::string>>(std::vector<std::string>{"R2", "R4", "R5", "R6", "auto"});
  auto noise = std::make_shared<std::string>("none");
  auto map_noise = std::make_shared<std::string>();
  auto seed = std::make_shared<std::uint64_t>(1);
  auto json = std::make_shared<std::string>();
  auto synthetic = std::make_shared<int>(0);
  auto quiet = std::make_shared<bool>(false);
  auto train = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand("eval",
      "Evaluate regressors on real people: avatars from each subject's Virtual Caliper inputs, compared with their "
      "ANSUR II measurements (paper Table 1 and held-out accuracy)");
  cmd->add_option("--subjects", o->subjects, "CSV in the ANSUR II public format (both sexes may be mixed)")->required();
  cmd->add_option("--regressor", *regressors, "regressors to evaluate, comma separated (R2, R4, R5, R6, auto, map)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--noise", *noise, "simulated measurement noise from the paper's Table 2: none, self or other")
      ->capture_default_str();
  cmd->add_option("--map-noise", *map_noise,
                  "noise setting the map estimator assumes: exact, self or other (default: none → exact, else as --noise)")
      ->check(CLI::IsMember({"exact", "self", "other"}));
  cmd->add_option("--seed", *seed, "seed of the simulated noise")->capture_default_str();
  cmd->add_option("--model", o->model, "body model family or path")->capture_default_str();
  cmd->add_option("--json", *json, "write the results as JSON to this file");
  cmd->add_option("--synthetic", *synthetic,
                  "also run the synthetic surface study on this many bodies per sex drawn from the model (0 = off)");
  cmd->add_option("--train", *train,
                  "ANSUR II-format CSV the linear limit is fitted on (default: 10-fold cross-validation over --subjects)");
  cmd->add_flag("-q,--quiet", *quiet, "no tables on stdout");
  cmd->callback([=] {
    EvaluationOptions opt;
    opt.regressors = *regressors;
    opt.noise = parse_noise(*noise);
    opt.map_noise = *map_noise;
    opt.seed = *seed;
    opt.threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    opt.progress = progress_bar("evaluating subjects");
    if (*synthetic < 0 || *synthetic > 100000)
      throw Error(ErrorKind::OutOfRange, "--synthetic must be in [0, 100000]", "--synthetic");
    const auto subjects = read_ansur_csv(o->subjects);
    if (subjects.empty()) throw Error(ErrorKind::Format, "'" + o->subjects + "' has no subjects", "--subjects");
    std::vector<AnsurSubject> training;
    if (!train->empty()) {
      training = read_ansur_csv(*train);
      opt.linear_training = &training;
    }
    const auto start = std::chrono::steady_clock::now();
    const auto builders = builders_for(o->model);  // one trained builder per sex, shared by the study below
    const Evaluation ev = evaluate_subjects(subjects, builders, opt);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    nlohmann::ordered_json result = nlohmann::ordered_json::parse(evaluation_json(ev));
    if (*synthetic > 0) {
      nlohmann::ordered_json study_json;
      for (Sex sex : {Sex::Female, Sex::Male}) {
        auto builder = builders(sex);
        for (const auto& [r, st] : synthetic_surface_study(*builder, opt.regressors, opt.noise, *synthetic, opt.seed)) {
          study_json[to_string(sex)][r] = {{"mean_cm", st.mean_cm}, {"max_cm", st.max_cm}, {"worst_cm", st.worst_cm}};
          if (!*quiet)
            std::cout << "synthetic " << to_string(sex) << " " << r << ": mean vertex distance " << std::fixed
                      << std::setprecision(2) << st.mean_cm << " cm, mean max " << st.max_cm << " cm\n";
        }
      }
      result["synthetic"] = study_json;
      result["synthetic_bodies_per_sex"] = *synthetic;
    }
    const std::string text = result.dump(2) + "\n";
    if (!*quiet) {
      std::cout << ev.subjects << " subjects, noise " << to_string(ev.noise) << ", " << std::fixed << std::setprecision(2)
                << seconds << " s; linear limit: " << ev.linear_limit_fitted_on << "\n";
      print_table("regressor", ev.regressors);
      print_table("baseline", ev.baselines);
    }
    if (!json->empty()) {
      write_file(*json, text);
      std::cout << "wrote " << *json << "\n";
    }
  });
}

void register_batch(CLI::App& app) {
  auto o = std::make_shared<SubjectsOptions>();
  auto out = std::make_shared<std::string>();
  auto regressor = std::make_shared<std::string>("auto");
  auto format = std::make_shared<std::string>("glb");
  CLI::App* cmd = app.add_subcommand("batch", "Write one avatar and one JSON report per row of an ANSUR II-format CSV");
  cmd->add_option("--subjects", o->subjects, "CSV in the ANSUR II public format")->required();
  cmd->add_option("--out", *out, "output folder (created if missing)")->required();
  cmd->add_option("--regressor", *regressor, "R2, R4, R5, R6, auto, map or a comma list of measurements")->capture_default_str();
  cmd->add_option("--format", *format, "glb or obj")->check(CLI::IsMember({"glb", "obj"}))->capture_default_str();
  cmd->add_option("--model", o->model, "body model family or path")->capture_default_str();
  cmd->callback([=] {
    const auto subjects = read_ansur_csv(o->subjects);
    std::error_code ec;
    std::filesystem::create_directories(*out, ec);
    if (ec) throw Error(ErrorKind::Io, "cannot create '" + *out + "': " + ec.message(), "--out");
    auto builder_for = builders_for(o->model);
    auto progress = progress_bar("writing avatars");
    int done = 0;
    for (const auto& s : subjects) {
      auto builder = builder_for(s.sex);
      AvatarRequest request;
      request.measurements = virtual_caliper_inputs(s);
      request.regressor = *regressor;
      const Avatar a = builder->build(request);
      // Subject ids become file names: keep them to safe characters.
      std::string id;
      for (char c : s.id) id += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ? c : '_';
      const std::string base = *out + "/" + (id.empty() ? std::to_string(done) : id);
      if (*format == "glb") save_glb(base + ".glb", builder->model(), a.rest_vertices);
      else write_file(base + ".obj", write_obj(a.rest_vertices, builder->model().faces(), builder->model().data().uv_coordinates,
                                                  builder->model().data().uv_faces, "Caliper avatar, subject " + s.id));
      write_file(base + ".json", avatar_report_json(builder->model(), a));
      progress(++done, static_cast<int>(subjects.size()));
    }
    std::cout << "wrote " << done << " avatars and reports to " << *out << "\n";
  });
}

}  // namespace caliper::cli
