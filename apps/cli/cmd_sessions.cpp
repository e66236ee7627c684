// `caliper sessions list|export|pair|delete`: capture sessions (docs/capture.md) stored by
// `caliper serve` in the data folder's sessions.db.
#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

#include "caliper/capture/body_image_task.h"
#include "caliper/capture/measurement_set.h"
#include "caliper/capture/service.h"
#include "common.h"

namespace caliper::cli {

namespace {

std::string database_for(const std::string& data_dir) {
  return data_dir.empty() ? capture::SessionStore::default_path() : capture::SessionStore::path_in(data_dir);
}

// These commands only read or remove: opening a database that is not there would create it (and
// its folder), so a mistyped --data would leave files behind and report "no sessions".
std::optional<capture::CaptureService> open_existing(const std::string& data_dir) {
  const std::string db = database_for(data_dir);
  std::error_code ec;
  if (!std::filesystem::exists(db, ec)) return std::nullopt;
  return std::optional<capture::CaptureService>(std::in_place, capture::CaptureServiceOptions{db, capture::ProfileRegistry::builtin(), {}});
}

capture::CaptureService& existing_or_throw(std::optional<capture::CaptureService>& svc, const std::string& data_dir,
                                           const std::string& id) {
  if (!svc)
    throw Error(ErrorKind::InvalidArgument, "no capture session '" + id + "': there is no " + database_for(data_dir) +
                                                " (is --data right?)", "id");
  return *svc;
}

capture::Session find_or_throw(capture::CaptureService& svc, const std::string& id) {
  auto s = svc.find(id);
  if (!s) throw Error(ErrorKind::InvalidArgument, "no capture session '" + id + "' in " + svc.database_path() + " (see `caliper sessions list`)", "id");
  return *s;
}

}  // namespace

void register_sessions(CLI::App& app) {
  auto data_dir = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand("sessions", "List, export, re-pair or delete capture sessions (measured in VR with `caliper serve`)");
  cmd->add_option("--data", *data_dir, "data folder holding sessions.db (default: $XDG_DATA_HOME/caliper or ~/.local/share/caliper)");
  cmd->require_subcommand(1);
  cmd->fallthrough();  // `caliper sessions list --data DIR` as well as `caliper sessions --data DIR list`

  CLI::App* list = cmd->add_subcommand(
      "list", "One line per session, newest first: id, created, state, progress, body-image tasks (answered/all), values");
  list->callback([=] {
    auto svc = open_existing(*data_dir);
    if (!svc) {
      std::cout << "no capture sessions: there is no " << database_for(*data_dir) << "\n";
      return;
    }
    const auto sessions = svc->list();
    if (sessions.empty()) {
      std::cout << "no capture sessions in " << svc->database_path() << "\n";
      return;
    }
    std::cout << std::left << std::setw(16) << "id" << std::setw(22) << "created" << std::setw(11) << "state" << std::setw(7)
              << "steps" << std::setw(7) << "mode" << std::setw(7) << "tasks" << "values (cm, kg)\n";
    for (const auto& s : sessions) {
      const auto& p = s.protocol;
      std::ostringstream values;
      values << std::fixed << std::setprecision(1);
      for (const auto& [name, v] : p.measurement_set()) values << name << "=" << v << " ";
      if (p.sex()) values << "sex=" << to_string(*p.sex());
      const auto tasks = svc->tasks(s.id).value_or(std::vector<capture::BodyImageTask>{});
      const auto answered = std::count_if(tasks.begin(), tasks.end(), [](const auto& t) { return t.answer.has_value(); });
      std::cout << std::left << std::setw(16) << s.id << std::setw(22) << s.created << std::setw(11) << to_string(p.state())
                << std::setw(7) << (std::to_string(p.steps_done()) + "/" + std::to_string(p.steps_total())) << std::setw(7)
                << to_string(p.config().mode) << std::setw(7) << (std::to_string(answered) + "/" + std::to_string(tasks.size()))
                << values.str() << "\n";
    }
  });

  auto id = std::make_shared<std::string>();
  auto output = std::make_shared<std::string>();
  auto format = std::make_shared<std::string>();
  CLI::App* exp = cmd->add_subcommand(
      "export",
      "Write a session's measurement set (JSON with its body-image tasks, or CSV; `caliper avatar --measurements` reads "
      "both) or its body-image tasks as CSV (tasks-csv)");
  exp->add_option("id", *id, "session id (s-…)")->required();
  exp->add_option("-o,--output", *output, "output file (.json or .csv); without it, JSON on standard output");
  exp->add_option("--format", *format, "json, csv or tasks-csv (default: from the output's extension, else json)")
      ->check(CLI::IsMember({"json", "csv", "tasks-csv"}));
  exp->callback([=] {
    auto svc = open_existing(*data_dir);
    const capture::Session s = find_or_throw(existing_or_throw(svc, *data_dir, *id), *id);
    const MeasurementSetFile set = measurement_set_of(s.protocol);
    std::string fmt = *format;
    if (fmt.empty()) fmt = output->size() >= 4 && output->substr(output->size() - 4) == ".csv" ? "csv" : "json";
    const std::vector<capture::BodyImageTask> tasks = svc->tasks(s.id).value_or(std::vector<capture::BodyImageTask>{});
    const std::string text = fmt == "csv"         ? write_measurement_set_csv(set)
                             : fmt == "tasks-csv" ? capture::write_body_image_tasks_csv(tasks)
                                                  : capture::write_session_json(set, tasks);
    if (s.protocol.state() != capture::SessionState::Done)
      std::cerr << "caliper sessions: warning: session " << s.id << " is not finished (state " << to_string(s.protocol.state())
                << "); exporting the values it has\n";
    if (output->empty()) {
      std::cout << text;
    } else {
      write_file(*output, text);
      std::cout << "wrote " << *output << "\n";
    }
  });

  auto pair_id = std::make_shared<std::string>();
  CLI::App* pair = cmd->add_subcommand(
      "pair", "Issue a new pairing code for a session (the old code stops working; unlocks a session locked by wrong codes)");
  pair->add_option("id", *pair_id, "session id (s-…)")->required();
  pair->callback([=] {
    auto svc = open_existing(*data_dir);
    find_or_throw(existing_or_throw(svc, *data_dir, *pair_id), *pair_id);
    const auto code = svc->reissue_pairing(*pair_id);
    if (!code) throw Error(ErrorKind::InvalidArgument, "no capture session '" + *pair_id + "'", "id");
    std::cout << "new pairing code for " << *pair_id << ": " << *code << "\n";
  });

  auto del_id = std::make_shared<std::string>();
  CLI::App* del = cmd->add_subcommand("delete", "Delete a session and all its points");
  del->add_option("id", *del_id, "session id (s-…)")->required();
  del->callback([=] {
    auto svc = open_existing(*data_dir);
    find_or_throw(existing_or_throw(svc, *data_dir, *del_id), *del_id);
    svc->remove(*del_id);
    std::cout << "deleted " << *del_id << "\n";
  });
}

}  // namespace caliper::cli
