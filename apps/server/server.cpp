// The HTTP transport: cpp-httplib for parsing, routing and writing, the connection front
// (connection_front.h) for holding connections, a body-size limit, the API under /api/ and the
// front end's static files. httplib.h is included only by this file and connection_front.cpp: its
// <resolv.h> defines a `_res` macro that breaks Eigen, and no Eigen header is reachable from either.
#include "server.h"

#include <httplib.h>
#include <sys/socket.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <type_traits>

#include "caliper/errors.h"
#include "connection_front.h"
#include "host_check.h"
#include "static_files.h"
#include "tls_certificate.h"

namespace caliper::server {
namespace {

// httplib's Server or SSLServer with its per-connection loop (a worker held for as long as the
// connection is open) replaced by the connection front: httplib hands over each accepted
// socket, and the front calls back into httplib for each whole request it has received.
template <class HttplibServer>
class FrontedServer final : public HttplibServer {
 public:
  using HttplibServer::HttplibServer;

  void attach(ConnectionFront* front) { front_ = front; }
  bool process_one_request(httplib::Stream& stream, bool close_connection, bool& connection_closed) {
    return this->process_request(stream, close_connection, connection_closed, nullptr);
  }

 private:
  bool process_and_close_socket(socket_t socket) override {
    front_->admit(socket);
    return true;
  }

  ConnectionFront* front_ = nullptr;
};

// httplib gives every accepted socket to its task queue; the front takes it at once, on the
// accept thread, so accepting never waits for a worker.
class AdmitOnAcceptThread final : public httplib::TaskQueue {
 public:
  void enqueue(std::function<void()> admit) override { admit(); }
  void shutdown() override {}
};

}  // namespace

struct Server::Impl {
  ServerOptions options;
  Api api;
  std::unique_ptr<httplib::Server> owned_http;  // a FrontedServer<httplib::SSLServer> with --https
  httplib::Server& http;
  std::unique_ptr<ConnectionFront> front;  // after `api` and `http`: its workers use both until it stops
  int port = -1;
  int listen_socket = -1;  // captured from httplib to raise its listen backlog

  explicit Impl(ServerOptions o)
      : options(std::move(o)), api(api_options(options)), owned_http(make_http(options)), http(*owned_http) {
    if (options.https) front = make_front(static_cast<FrontedServer<httplib::SSLServer>&>(http));
    else front = make_front(static_cast<FrontedServer<httplib::Server>&>(http));
  }

  // What the API is told about how it is reached: the scheme, and on all interfaces the LAN
  // addresses a headset can open (the capture page's QR code).
  static ApiOptions api_options(const ServerOptions& o) {
    ApiOptions a = o.api;
    a.https = o.https;
    if (o.host == "0.0.0.0" && a.headset_hosts.empty()) a.headset_hosts = lan_addresses();
    return a;
  }

  static std::unique_ptr<httplib::Server> make_http(const ServerOptions& o) {
    if (!o.https) return std::make_unique<FrontedServer<httplib::Server>>();
    auto ssl = std::make_unique<FrontedServer<httplib::SSLServer>>(o.cert_file.c_str(), o.key_file.c_str());
    if (!ssl->is_valid())
      throw Error(ErrorKind::Io, "cannot serve HTTPS with certificate '" + o.cert_file + "' and key '" + o.key_file +
                                     "' (missing, unreadable, or not a matching PEM pair)", "--cert");
    return ssl;
  }

  template <class Fronted>
  std::unique_ptr<ConnectionFront> make_front(Fronted& fronted) const {
    ssl_ctx_st* tls = nullptr;
    if constexpr (std::is_same_v<Fronted, FrontedServer<httplib::SSLServer>>) tls = fronted.ssl_context();
    auto made = std::make_unique<ConnectionFront>(
        options.connections, options.max_body_bytes, std::max(1, options.threads), tls,
        [&fronted](httplib::Stream& stream, bool close_connection, bool& connection_closed) {
          return fronted.process_one_request(stream, close_connection, connection_closed);
        });
    fronted.attach(made.get());
    return made;
  }

  static void send(httplib::Response& res, const ApiResponse& r) {
    res.status = r.status;
    res.set_content(r.body, r.content_type.c_str());
    if (!r.download_name.empty())
      res.set_header("Content-Disposition", "attachment; filename=\"" + r.download_name + "\"");
    res.set_header("Cache-Control", "no-store");
  }

  void handle_api(const httplib::Request& req, httplib::Response& res) const {
    ApiRequest a;
    a.method = req.method;
    a.path = req.path;
    for (const auto& [k, v] : req.params) a.query.emplace(k, v);
    a.body = req.body;
    a.content_type = req.get_header_value("Content-Type");
    for (const auto& [name, value] : req.headers) {
      std::string key = name;
      for (auto& c : key) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      a.headers.emplace(key, value);
    }
    a.remote_address = req.remote_addr;
    a.local_address = req.local_addr;
    send(res, api.handle(a));
  }

  void handle_static(const httplib::Request& req, httplib::Response& res) const {
    const auto file = resolve_static_path(options.web_root, req.path);
    if (!file) {
      send(res, error_response(404, "not found: " + req.path, "path", "not_found"));
      return;
    }
    std::ifstream in(*file, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    if (!in) {
      send(res, error_response(404, "not found: " + req.path, "path", "not_found"));
      return;
    }
    res.set_content(bytes.str(), mime_type_for(*file).c_str());
    res.set_header("Cache-Control", "no-cache");
  }

  void dispatch(const httplib::Request& req, httplib::Response& res) const {
    res.set_header("X-Content-Type-Options", "nosniff");
    res.set_header("Referrer-Policy", "no-referrer");
    if (const std::string host = req.get_header_value("Host"); !host_is_allowed(host, options.allowed_hosts)) {
      send(res, error_response(403,
                               "this server answers requests addressed to an IP address or localhost, not to '" + host +
                                   "' (protection against DNS rebinding); start it with --allow-host NAME to use a host name",
                               "Host", "host_not_allowed"));
      return;
    }
    const bool write = req.method != "GET" && req.method != "HEAD" && req.method != "OPTIONS";
    if (write && !origin_is_same_host(req.get_header_value("Origin"), req.get_header_value("Host"))) {
      send(res, error_response(403,
                               "writes are accepted only from this server's own pages, not from '" +
                                   req.get_header_value("Origin") + "' (protection against cross-site requests)",
                               "Origin", "origin_not_allowed"));
      return;
    }
    // A preflight gets no Access-Control-Allow-* header, so browsers never send another site's
    // non-simple request (JSON POST, DELETE) at all.
    if (req.method == "OPTIONS") {
      res.status = 204;
      res.set_header("Allow", "GET, HEAD, POST, PUT, DELETE, PATCH, OPTIONS");
      return;
    }
    if (req.path.rfind("/api/", 0) == 0) handle_api(req, res);
    else if (req.method == "GET" || req.method == "HEAD") handle_static(req, res);
    else send(res, error_response(405, req.method + " is only allowed on /api/ endpoints", "method", "method_not_allowed"));
  }
};

Server::Server(ServerOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {
  Impl& s = *impl_;
  s.http.new_task_queue = [] { return new AdmitOnAcceptThread; };
  s.http.set_payload_max_length(s.options.max_body_bytes);
  // What httplib advertises in `Keep-Alive: timeout=…, max=…` (the front enforces both). The
  // timeout is a second short of the front's idle limit, so a client that honours it closes an
  // idle connection before the server does, instead of sending a request into a closing socket.
  const auto& limits = s.options.connections;
  s.http.set_keep_alive_timeout(std::max<time_t>(1, static_cast<time_t>(limits.idle_timeout_s) - 1));
  s.http.set_keep_alive_max_count(static_cast<size_t>(std::max(1, limits.max_requests_per_connection)));
  // httplib listens with a backlog of 5, so a burst of clients overflows the accept queue and
  // some connections fail. Remember the listening socket (SO_REUSEADDR as httplib would, but not
  // SO_REUSEPORT, which would let another process share the port) and re-listen after binding.
  s.http.set_socket_options([&s](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    s.listen_socket = sock;
  });
  // No response compression: on loopback it only costs time, and httplib 0.11 picks brotli at
  // its slowest quality whenever the client accepts it (over 20 s for three.js's 1.5 MB, and
  // milliseconds on every avatar). httplib decides from the request's Accept-Encoding when it
  // writes the response, so the header is dropped here, before routing. The Request object is
  // httplib's own non-const local; only the handler interface hands it out as const.
  s.http.set_pre_routing_handler([](const httplib::Request& req, httplib::Response&) {
    const_cast<httplib::Request&>(req).headers.erase("Accept-Encoding");
    return httplib::Server::HandlerResponse::Unhandled;
  });
  auto handler = [&s](const httplib::Request& req, httplib::Response& res) { s.dispatch(req, res); };
  s.http.Get(".*", handler);
  s.http.Post(".*", handler);
  s.http.Put(".*", handler);
  s.http.Delete(".*", handler);
  s.http.Patch(".*", handler);
  s.http.Options(".*", handler);
  // httplib's own refusals (413 for an oversized body, 400 for a malformed request line) come
  // without a body; give them the API's JSON error shape.
  s.http.set_error_handler(httplib::Server::HandlerWithResponse([](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
    std::string message = "request refused";
    std::string field;
    std::string kind = "bad_request";
    if (res.status == 413) {
      message = "the request body is too large";
      field = "body";
      kind = "payload_too_large";
    } else if (res.status == 404) {
      message = "not found";
      kind = "not_found";
    }
    const ApiResponse e = error_response(res.status, message, field, kind);
    res.set_content(e.body, e.content_type.c_str());
    return httplib::Server::HandlerResponse::Handled;
  }));
  if (s.options.log)
    s.http.set_logger([&s](const httplib::Request& req, const httplib::Response& res) {
      s.options.log(req.method + " " + req.path + " " + std::to_string(res.status) + " " + std::to_string(res.body.size()) + " B");
    });
}

Server::~Server() {
  if (impl_->http.is_running()) impl_->http.stop();
}

int Server::bind() {
  Impl& s = *impl_;
  if (s.options.port < 0 || s.options.port > 65535)
    throw Error(ErrorKind::OutOfRange, "port must be in [0, 65535] (0 = any free port)", "--port");
  if (s.options.port == 0) {
    s.port = s.http.bind_to_any_port(s.options.host);
  } else {
    s.port = s.http.bind_to_port(s.options.host, s.options.port) ? s.options.port : -1;
  }
  if (s.port < 0)
    throw Error(ErrorKind::Io,
                "cannot listen on " + s.options.host + ":" + std::to_string(s.options.port) +
                    " (in use or not a local address; try --port 0 for any free port)",
                "--port");
  if (s.listen_socket >= 0) ::listen(s.listen_socket, SOMAXCONN);
  return s.port;
}

int Server::port() const { return impl_->port; }

void Server::run() {
  if (impl_->port < 0) bind();
  impl_->http.listen_after_bind();
  impl_->front->stop();  // accepting has ended (stop() or a failure): close what is still open
}

void Server::stop() { impl_->http.stop(); }

const Api& Server::api() const { return impl_->api; }

int Server::open_connections() const { return impl_->front->open_connections(); }
std::uint64_t Server::accepted_connections() const { return impl_->front->accepted_connections(); }

}  // namespace caliper::server
