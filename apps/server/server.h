// The Caliper HTTP server behind `caliper serve`: the JSON API (api.h) under /api/ and the web
// front end's static files from a web root. httplib stays inside server.cpp.
#pragma once
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "api.h"

namespace caliper::server {

struct ServerOptions {
  std::string host = "127.0.0.1";
  int port = 8080;                         // 0: any free port (see Server::port())
  std::string web_root;                    // folder of the built front end (web/dist)
  int threads = 32;                        // worker threads; each open connection holds one
  std::size_t max_body_bytes = 1 << 20;    // larger request bodies get 413
  ApiOptions api;
  std::function<void(const std::string&)> log;  // one line per request; empty: quiet
  // HTTPS (headsets need a secure context for WebXR): PEM certificate and private key files.
  bool https = false;
  std::string cert_file, key_file;
  // Host names answered besides IP addresses and localhost (host_check.h); others get 403.
  std::vector<std::string> allowed_hosts;
};

class Server {
 public:
  explicit Server(ServerOptions options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  // Binds the socket; returns the port (the chosen one when options.port is 0).
  // Throws caliper::Error(Io) when the address cannot be bound.
  int bind();
  int port() const;
  // Serves until stop() is called (from another thread or a signal handler's helper thread).
  void run();
  void stop();
  const Api& api() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caliper::server
