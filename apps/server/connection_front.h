// The server's connection front: what stands between accepted sockets and the worker threads.
//
// httplib alone gives every open connection a worker thread for as long as it is open, and its
// read timeout is per read, so a client sending one byte every few seconds holds a worker for
// ever; a few dozen such clients deny all service (docs/reliability.md "Slow clients").
// Here a worker is given a connection only once a whole request has arrived, headers and body:
// one thread, the waiting room, polls every connection that is idle, shaking hands (TLS) or
// still receiving, with no worker held, and enforces
//   - a deadline for a whole request (headers + body) from its first byte, not per read,
//   - a short idle wait for a kept-alive connection's next request,
//   - a bounded TLS handshake,
//   - a cap on open connections per client address (503 + Retry-After beyond it) and in all,
//   - bounded buffers (bodies beyond a small per-connection allowance share one budget).
// Refusals (408, 411, 413, 431, 503) are answered by the waiting room itself, which then reads
// and drops the rest of the request for a moment so the client sees the answer, not a reset.
// Workers run httplib's own request processing (Server::process_request) on a stream that
// serves the received bytes and collects the response, send what the socket takes at once, and
// hand the connection back to the waiting room, which sends the rest to a slow reader (within a
// response deadline; bounded by a shared budget) and waits for a kept-alive connection's next
// request.
//
// Internal to apps/server: included by server.cpp and the front's own .cpp only.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>

#include "server.h"

namespace httplib {
class Stream;
}
struct ssl_ctx_st;  // OpenSSL's SSL_CTX

namespace caliper::server {

// Runs one request from the stream (httplib's Server::process_request). `close_connection`:
// answer with Connection: close. Sets `connection_closed` when the client asked to close.
// Returns false when the connection failed (nothing more can be read or written).
using RequestProcessor = std::function<bool(httplib::Stream& stream, bool close_connection, bool& connection_closed)>;

class ConnectionFront {
 public:
  // `max_body_bytes`: larger request bodies get 413 (ServerOptions::max_body_bytes).
  // `tls`: the server's TLS context (httplib::SSLServer::ssl_context()), or null for plain HTTP.
  ConnectionFront(const ConnectionLimits& limits, std::size_t max_body_bytes, int worker_threads, ssl_ctx_st* tls,
                  RequestProcessor process);
  ~ConnectionFront();  // stop()s
  ConnectionFront(const ConnectionFront&) = delete;
  ConnectionFront& operator=(const ConnectionFront&) = delete;

  // Takes an accepted socket (ownership included); never blocks. Called from the accept loop.
  void admit(int socket);
  // Closes every waiting connection, lets workers finish the requests they hold, joins threads.
  void stop();

  // Connections open now (waiting, being served, or being refused), for tests and the load report.
  int open_connections() const;
  // Sockets handed to admit() so far, admitted or dropped at once: with open_connections(), tells
  // a test when the server has dealt with a connection it just opened.
  std::uint64_t accepted_connections() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caliper::server
