// `caliper eval` and `caliper batch`: avatars for every row of an ANSUR II-format CSV.
#include <algorithm>
#include <filesystem>
#include <optional>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <thread>
#include <nlohmann/json.hpp>

#include "caliper/capture/measurement_set.h"
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

namespace {

// A participant id as a file name: letters, digits, '-', '_' and '.' kept, anything else (path
// separators included) becomes '_', and a leading '.' too, so no id names a hidden file, "..",
// or a path outside the output folder.
std::string file_name_of(const std::string& participant) {
  std::string name;
  for (char c : participant)
    name += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' ? c : '_';
  if (!name.empty() && name[0] == '.') name[0] = '_';
  return name.substr(0, 100);
}

}  // namespace

void register_batch(CLI::App& app) {
  auto o = std::make_shared<SubjectsOptions>();
  auto out = std::make_shared<std::string>();
  auto regressor = std::make_shared<std::string>("auto");
  auto format = std::make_shared<std::string>("glb");
  auto sex = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand("batch",
      "Write one avatar and one JSON report per person of a table: a spreadsheet in cm and kg (one row per person, "
      "a header of measurement names, an id column) or an ANSUR II-format CSV");
  cmd->add_option("--subjects", o->subjects,
                  "CSV, one person per row: id,sex,height,weight,… in cm and kg (',' or ';' separated, decimal "
                  "commas allowed; docs/cli.md), or the ANSUR II public format")
      ->required();
  cmd->add_option("--out", *out, "output folder (created if missing); files are named after the id column")->required();
  cmd->add_option("--sex", *sex, "female, male or neutral: the sex of rows without a sex column or value");
  cmd->add_option("--regressor", *regressor, "R2, R4, R5, R6, auto, map or a comma list of measurements")->capture_default_str();
  cmd->add_option("--format", *format, "the avatars' files, as `avatar -o` writes them: glb, vrm, fbx or obj")
      ->check([](const std::string& name) { return avatar_format_named(name) ? "" : "must be glb, vrm, fbx or obj"; })
      ->capture_default_str();
  cmd->add_option("--model", o->model, "body model family or path")->capture_default_str();
  cmd->callback([=] {
    MeasurementTable table = read_measurement_table(o->subjects);
    const std::optional<Sex> default_sex = sex->empty() ? std::nullopt : std::optional<Sex>(parse_sex(*sex));
    std::error_code ec;
    std::filesystem::create_directories(*out, ec);
    if (ec) throw Error(ErrorKind::Io, "cannot create '" + *out + "': " + ec.message(), "--out");
    auto builder_for = builders_for(o->model);
    auto progress = progress_bar("writing avatars");
    std::map<std::string, int> line_of_file;  // two ids may sanitise to one name
    int done = 0, handled = 0;
    for (const MeasurementRow& row : table.rows) {
      try {
        const std::optional<Sex> row_sex = row.set.sex ? row.set.sex : default_sex;
        if (!row_sex)
          throw Error(ErrorKind::InvalidArgument, "sex is not given: add a sex column (female or male) or --sex", "sex");
        auto builder = builder_for(*row_sex);
        AvatarRequest request;
        request.measurements = measurements_from_edge(row.set.edge);
        request.regressor = *regressor;
        request.noise = row.set.measured_by.value_or("exact");
        const Avatar a = builder->build(request);
        std::string name = file_name_of(row.participant);
        if (name.empty()) name = "line-" + std::to_string(row.line);
        if (const auto [it, fresh] = line_of_file.emplace(name, row.line); !fresh) name += "-line-" + std::to_string(row.line);
        const std::string base = *out + "/" + name;
        save_avatar(base + "." + to_string(*avatar_format_named(*format)), builder->model(), a, "--out");
        write_file(base + ".json", avatar_report_json(builder->model(), a));
        ++done;
      } catch (const Error& e) {
        // A broken installation or output folder fails every row alike: stop at once.
        if (e.from_installation() || e.kind() == ErrorKind::Io) throw;
        table.skipped.push_back({row.line, e.field(), "line " + std::to_string(row.line) + ": " + e.what()});
      }
      progress(++handled, static_cast<int>(table.rows.size()));
    }
    std::cout << "wrote " << done << " avatars and reports to " << *out << "\n";
    if (table.skipped.empty()) return;
    std::sort(table.skipped.begin(), table.skipped.end(), [](const SkippedRow& a, const SkippedRow& b) { return a.line < b.line; });
    std::cerr << "caliper: skipped " << table.skipped.size() << " row" << (table.skipped.size() == 1 ? "" : "s") << " of '"
              << o->subjects << "':\n";
    for (const SkippedRow& s : table.skipped) std::cerr << "  " << s.reason << "\n";
    throw Finished{kSomeRowsSkipped};
  });
}

}  // namespace caliper::cli
