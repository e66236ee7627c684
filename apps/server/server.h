// The Caliper HTTP server behind `caliper serve`: the JSON API (api.h) under /api/ and the web
// front end's static files from a web root. httplib stays inside server.cpp.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "api.h"

namespace caliper::server {

// How many connections the server keeps open and for how long (apps/server/connection_front.h;
// docs/api.md "Limits and concurrency"). A connection holds no worker thread while it is idle or
// still sending its request, so these bound sockets and buffers, not threads.
struct ConnectionLimits {
  int max_per_address = 16;           // open connections from one client address; the next get 503 + Retry-After
  int max_total = 512;                // open connections in all; beyond it a new connection is closed unanswered
  double request_deadline_s = 10;     // a whole request (headers and body) must arrive within this of its first byte
  double idle_timeout_s = 5;          // a connection is closed when no request starts within this (new or kept alive)
  double tls_handshake_s = 5;         // a TLS handshake must finish within this of the connection's accept
  double response_deadline_s = 10;    // a response must be written within this of its request being complete
  int max_requests_per_connection = 1000;  // then the connection is closed (the client reconnects)
};

struct ServerOptions {
  std::string host = "127.0.0.1";
  int port = 8080;                         // 0: any free port (see Server::port())
  std::string web_root;                    // folder of the built front end (web/dist)
  int threads = 32;                        // worker threads; a connection holds one only while its request runs
  std::size_t max_body_bytes = 1 << 20;    // larger request bodies get 413
  ConnectionLimits connections;
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
  // Connections open now: idle, receiving, being served or being refused.
  int open_connections() const;
  // Connections accepted so far, admitted or dropped at once (ConnectionFront::accepted_connections()).
  std::uint64_t accepted_connections() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caliper::server
