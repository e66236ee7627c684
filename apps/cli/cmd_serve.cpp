// `caliper serve`: the desktop tool (paper §4.3, §5) as a local web app. Serves the JSON API
// (docs/api.md) and the front end built into web/dist (docs/desktop-tool.md) until Ctrl+C.
#include <atomic>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <pthread.h>
#include <thread>

#include "caliper/capture/store.h"
#include "capture_api.h"
#include "common.h"
#include "host_check.h"
#include "server.h"
#include "tls_certificate.h"

namespace caliper::cli {

void register_serve(CLI::App& app) {
  auto opts = std::make_shared<server::ServerOptions>();
  // An installed program serves its own copy of the page (share/caliper/web); a built one the
  // source tree's web/dist.
  const std::string installed = installed_data_dir();
  opts->web_root = !installed.empty() && std::filesystem::is_directory(installed + "/web") ? installed + "/web"
                                                                                          : CALIPER_WEB_ROOT;
  auto quiet = std::make_shared<bool>(false);
  auto no_warm_up = std::make_shared<bool>(false);
  auto data_dir = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand("serve", "Run the desktop tool: a local web app to build, inspect and export avatars");
  cmd->add_option("--host", opts->host, "address to listen on (127.0.0.1 keeps it on this machine)")->capture_default_str();
  cmd->add_option("--port", opts->port, "TCP port; 0 picks a free one (printed)")->capture_default_str();
  cmd->add_option("--web-root", opts->web_root, "folder of the built front end (`node web/build.mjs` writes web/dist)")
      ->capture_default_str();
  cmd->add_option("--model", opts->api.default_model, "default body model (a family in the models folder)")->capture_default_str();
  cmd->add_option("--threads", opts->threads, "worker threads serving requests (1–256)")->capture_default_str();
  cmd->add_flag("--no-warm-up", *no_warm_up, "do not train the default model's regressors before listening");
  cmd->add_flag("-q,--quiet", *quiet, "do not log requests");
  // Capture (docs/capture.md): where sessions live, HTTPS for headsets.
  cmd->add_option("--data", *data_dir, "data folder for capture sessions (sessions.db) and the generated certificate "
                                       "(default: $XDG_DATA_HOME/caliper or ~/.local/share/caliper)");
  cmd->add_option("--capture-profiles", opts->api.capture_profiles_file,
                  "JSON file overriding controller tip offsets (docs/capture.md)");
  cmd->add_flag("--https", opts->https, "serve HTTPS (a headset needs it for WebXR); without --cert/--key a self-signed "
                                        "certificate is made once in the data folder");
  cmd->add_option("--cert", opts->cert_file, "PEM certificate for --https");
  cmd->add_option("--key", opts->key_file, "PEM private key for --https");
  cmd->add_option("--allow-host", opts->allowed_hosts,
                  "also answer requests addressed to this host name (repeatable); by default only IP addresses and "
                  "localhost are answered, so other web sites cannot reach the server through DNS rebinding");
  cmd->callback([=] {
    if (opts->threads < 1 || opts->threads > 256)
      throw Error(ErrorKind::OutOfRange, "--threads must be in [1, 256]", "--threads");
    // A default model or profiles file the server cannot use would otherwise fail every request
    // that relies on it; checked with the code those requests use, keeping the error's kind.
    try {
      server::require_known_model(opts->api, opts->api.default_model);
    } catch (const Error& e) {
      throw e.restated(std::string("--model: ") + e.what(), "--model");
    }
    if (!opts->api.capture_profiles_file.empty()) {
      try {
        server::check_capture_profiles_file(opts->api.capture_profiles_file);
      } catch (const Error& e) {
        throw e.restated(std::string("--capture-profiles: ") + e.what(), "--capture-profiles");
      }
    }
    // The sessions database is checked now, so a corrupt or foreign file stops the start-up
    // with a clear message instead of failing every capture request.
    const std::string db = data_dir->empty() ? capture::SessionStore::default_path() : capture::SessionStore::path_in(*data_dir);
    try {
      capture::SessionStore check(db);
    } catch (const Error& e) {
      if (!data_dir->empty()) throw;  // asked for explicitly: do not start without it
      std::cerr << "caliper serve: warning: capture sessions unavailable (" << e.what() << "); the desktop tool works\n";
    }
    opts->api.sessions_database = db;
    // Listening on a host name (not an address) means requests will carry that name.
    if (!server::host_is_allowed(opts->host, {})) opts->allowed_hosts.push_back(opts->host);
    if ((!opts->cert_file.empty() || !opts->key_file.empty()) && !opts->https)
      throw Error(ErrorKind::InvalidArgument, "--cert and --key need --https", "--https");
    if (opts->https && (opts->cert_file.empty() != opts->key_file.empty()))
      throw Error(ErrorKind::InvalidArgument, "give both --cert and --key, or neither (a self-signed certificate is made)", "--cert");
    if (opts->https && opts->cert_file.empty()) {
      std::vector<std::string> hosts = {"localhost", "127.0.0.1"};
      for (const auto& ip : server::lan_addresses()) hosts.push_back(ip);
      if (opts->host != "0.0.0.0" && opts->host != "127.0.0.1") hosts.push_back(opts->host);
      const auto files = server::ensure_self_signed_certificate(std::filesystem::path(db).parent_path().string(), hosts);
      opts->cert_file = files.cert_file;
      opts->key_file = files.key_file;
      std::cerr << "caliper serve: " << (files.created ? "made a self-signed certificate " : "using the certificate ")
                << files.cert_file << " (the headset's browser will ask you to accept it once)\n";
    }
    std::error_code ec;
    if (!std::filesystem::is_regular_file(std::filesystem::path(opts->web_root) / "index.html", ec))
      std::cerr << "caliper serve: warning: no index.html in " << opts->web_root
                << " — build the front end with `node web/build.mjs` (the API still works)\n";
    if (!*quiet) {
      auto log_mutex = std::make_shared<std::mutex>();
      opts->log = [log_mutex](const std::string& line) {
        std::lock_guard<std::mutex> lock(*log_mutex);
        std::cerr << line << "\n";
      };
    }
    // Signals go to one waiting thread, which stops the server cleanly (no work in a handler).
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);

    server::Server srv(*opts);
    const int port = srv.bind();
    if (!*no_warm_up) {
      std::cerr << "caliper serve: preparing " << opts->api.default_model << " (training the R2–R6 regressors)…\n";
      std::string problems;
      srv.api().warm_up(opts->api.default_model, &problems);
      if (!problems.empty()) std::cerr << "caliper serve: warning: " << problems;
    }
    std::atomic<bool> signalled{false};
    std::thread waiter([&srv, &signalled, signals] {
      int sig = 0;
      sigwait(&signals, &sig);
      signalled = true;
      srv.stop();
    });
    const std::string shown_host = opts->host == "0.0.0.0" ? "127.0.0.1" : opts->host;
    const std::string scheme = opts->https ? "https" : "http";
    std::cout << "Caliper desktop tool: open " << scheme << "://" << shown_host << ":" << port << "/ in a browser (Ctrl+C stops)"
              << std::endl;
    if (opts->host == "0.0.0.0") {
      for (const auto& ip : server::lan_addresses())
        std::cout << "Capture: open " << scheme << "://" << ip << ":" << port << "/capture.html in the headset's browser" << std::endl;
    } else {
      std::cout << "Capture: " << scheme << "://" << shown_host << ":" << port << "/capture.html"
                << (shown_host == "127.0.0.1" ? " (this machine only; a headset needs --host 0.0.0.0 --https)" : "") << std::endl;
    }
    srv.run();
    // run() also returns if listening fails; wake the waiter so it can be joined.
    if (!signalled) pthread_kill(waiter.native_handle(), SIGTERM);
    waiter.join();
    std::cout << "caliper serve: stopped" << std::endl;
  });
}

}  // namespace caliper::cli
