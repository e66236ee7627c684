// The connection front (connection_front.h): a waiting room that polls idle and incoming
// connections on one thread, and workers that get a connection only with a whole request in hand.
// Sockets are non-blocking throughout, so every wait is a poll() bounded by a deadline.
#include "connection_front.h"

#include <fcntl.h>
#include <httplib.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <openssl/err.h>
#include <openssl/ssl.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "api.h"
#include "client_group.h"

namespace caliper::server {
namespace {

using Clock = std::chrono::steady_clock;

// Request headers larger than this get 431 (httplib itself allows 8 KiB per line).
constexpr std::size_t kMaxHeaderBytes = 64 * 1024;
// What any connection may hold in the waiting room: headers and a small body (most requests).
constexpr std::size_t kBufferPerConnection = 2 * kMaxHeaderBytes;
// Larger bodies (up to the server's body limit) are received whole too, drawing the excess from
// this budget shared by all connections; while it is spent such requests get 503. So no worker
// ever waits for a request's bytes, and the waiting room holds at most
// max_total × kBufferPerConnection + kSharedBodyBudget (64 + 64 MiB by default).
constexpr std::size_t kSharedBodyBudget = 64u << 20;
// A client over its address's connection cap, or finding the budget spent, is told to come back
// after this (Retry-After).
constexpr int kRetryAfterSeconds = 2;
// Responses a slow reader has not taken yet wait in the waiting room, not in a worker, up to
// this much in all; beyond it a worker sends its response itself (within the response deadline).
constexpr std::size_t kSharedResponseBudget = 64u << 20;
// At the total cap a new connection is still let in, and a waiting connection of the address
// with the most open is closed instead (its longest-waiting one): a flood of idle connections
// from a few addresses cannot lock newcomers out. Up to this many are let in beyond the
// cap before the waiting room catches up; more are closed at once.
constexpr int kAdmittedBeyondTotal = 64;
// ... but only from an address with fewer open than this (a browser opens up to 6 per server):
// a flood's own reconnects cannot use up that room before a newcomer gets it.
constexpr int kMostOpenToGoBeyondTotal = 6;
// After a refusal the rest of the request is read and dropped for up to this long before the
// socket closes, so the client reads the refusal instead of a reset.
constexpr double kDrainSeconds = 2;

Clock::time_point after(double seconds) {
  return Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

// Milliseconds until `deadline` for poll(), rounded up; 0 once it has passed.
int ms_until(Clock::time_point deadline) {
  const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return static_cast<int>(std::clamp<long long>(left, 0, INT_MAX));
}

// Waits until `socket` has one of `events` (POLLIN or POLLOUT) or fails; false once `deadline` passes.
bool wait_for(int socket, short events, Clock::time_point deadline) {
  for (;;) {
    pollfd p{socket, events, 0};
    const int r = ::poll(&p, 1, ms_until(deadline));
    if (r > 0) return true;  // ready, or an error the next read or write reports
    if (r == 0 || errno != EINTR) return false;
  }
}

void numeric_address(const sockaddr_storage& a, socklen_t length, std::string& ip, int& port) {
  char host[NI_MAXHOST] = "";
  char service[NI_MAXSERV] = "";
  if (::getnameinfo(reinterpret_cast<const sockaddr*>(&a), length, host, sizeof host, service, sizeof service,
                    NI_NUMERICHOST | NI_NUMERICSERV) == 0) {
    ip = host;
    port = std::atoi(service);
  }
}

// One client connection. The waiting room or one worker owns it at a time; handing it over
// (through the front's mutex or the worker pool's queue) orders their accesses.
struct Connection {
  enum class Phase { Handshake, Idle, Receiving, Sending, Draining };

  int socket = -1;
  SSL* tls = nullptr;  // null for plain HTTP
  std::string address, local_address;
  std::string group;              // client_group(address): what the per-address cap counts
  int port = 0, local_port = 0;
  Phase phase = Phase::Idle;
  bool refused = false;           // over its address's cap: answered 503 at once
  bool peer_closed = false;       // the client shut down its side after sending
  bool tls_wants_write = false;   // the handshake waits for the socket to take data
  bool continue_sent = false;     // `100 Continue` was sent for the request being received
  std::string received;           // bytes received and not yet consumed by a request
  std::size_t receive_limit = kBufferPerConnection;  // more while a large body has budget reserved
  std::size_t reserved = 0;       // bytes of the shared body budget held for this request
  std::string outgoing;           // the response being sent
  std::size_t sent = 0;           // of `outgoing`
  std::size_t outgoing_reserved = 0;  // bytes of the shared response budget held while Sending
  short send_events = POLLOUT;    // what sending waits for (TLS may need to read first)
  bool close_after_sending = false;
  Clock::time_point deadline;          // of the current phase
  Clock::time_point waiting_since;     // when it last started waiting for a request (eviction order)
  int requests_served = 0;

  Connection() = default;
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;
  ~Connection() {
    if (tls) {
      SSL_shutdown(tls);  // one non-blocking attempt at close_notify
      SSL_free(tls);
    }
    if (socket >= 0) ::close(socket);
  }

  // The client's request has started: the whole of it must now arrive by the request deadline.
  void start_request(double request_deadline_s) {
    phase = Phase::Receiving;
    deadline = after(request_deadline_s);
  }
};

enum class Transfer { Done, WouldBlock, Failed };

// One non-blocking read into `out`; `n` is the byte count when Done (0: the peer closed).
Transfer read_some(Connection& c, char* out, std::size_t size, std::size_t& n, short& wait_events) {
  if (c.tls) {
    const int r = SSL_read(c.tls, out, static_cast<int>(std::min<std::size_t>(size, INT_MAX)));
    if (r > 0) return n = std::size_t(r), Transfer::Done;
    const int e = SSL_get_error(c.tls, r);
    if (e == SSL_ERROR_WANT_READ) return wait_events = POLLIN, Transfer::WouldBlock;
    if (e == SSL_ERROR_WANT_WRITE) return wait_events = POLLOUT, Transfer::WouldBlock;
    if (e == SSL_ERROR_ZERO_RETURN) return n = 0, Transfer::Done;
    return Transfer::Failed;
  }
  const ssize_t r = ::recv(c.socket, out, size, MSG_DONTWAIT);
  if (r >= 0) return n = std::size_t(r), Transfer::Done;
  if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return wait_events = POLLIN, Transfer::WouldBlock;
  return Transfer::Failed;
}

// One non-blocking write from `data`; `n` is the byte count written when Done.
Transfer write_some(Connection& c, const char* data, std::size_t size, std::size_t& n, short& wait_events) {
  if (c.tls) {
    const int r = SSL_write(c.tls, data, static_cast<int>(std::min<std::size_t>(size, INT_MAX)));
    if (r > 0) return n = std::size_t(r), Transfer::Done;
    const int e = SSL_get_error(c.tls, r);
    if (e == SSL_ERROR_WANT_READ) return wait_events = POLLIN, Transfer::WouldBlock;
    if (e == SSL_ERROR_WANT_WRITE) return wait_events = POLLOUT, Transfer::WouldBlock;
    return Transfer::Failed;
  }
  const ssize_t r = ::send(c.socket, data, size, MSG_DONTWAIT | MSG_NOSIGNAL);
  if (r >= 0) return n = std::size_t(r), Transfer::Done;
  if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return wait_events = POLLOUT, Transfer::WouldBlock;
  return Transfer::Failed;
}

// What a worker's httplib sees: the request the waiting room received, whole, and a buffer for
// the response. Nothing here touches the socket, so a worker never waits for the client.
class ConnectionStream final : public httplib::Stream {
 public:
  explicit ConnectionStream(Connection& c) : c_(c) {}

  bool is_readable() const override { return consumed_ < c_.received.size(); }
  // The response is collected whole and sent afterwards (Impl::serve), so a client that reads
  // slowly never holds the worker that built its answer.
  bool is_writable() const override { return true; }

  // Beyond the bytes received is the end: the request is whole (request_shape), so only a
  // request that lied about its length reads further, and httplib refuses it.
  ssize_t read(char* out, size_t size) override {
    const std::size_t n = std::min(size, c_.received.size() - consumed_);
    std::memcpy(out, c_.received.data() + consumed_, n);
    consumed_ += n;
    return ssize_t(n);
  }
  ssize_t write(const char* data, size_t size) override {
    c_.outgoing.append(data, size);
    return ssize_t(size);
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override { ip = c_.address, port = c_.port; }
  void get_local_ip_and_port(std::string& ip, int& port) const override { ip = c_.local_address, port = c_.local_port; }
  socket_t socket() const override { return c_.socket; }

  // Drops what the request consumed; anything after it (a pipelined request) stays received.
  void forget_consumed() {
    c_.received.erase(0, consumed_);
    consumed_ = 0;
  }

 private:
  Connection& c_;
  std::size_t consumed_ = 0;
};

// Case-insensitive: does the header block have a field `name` (lower case, with the colon)?
// Returns its value's start, or npos.
std::size_t find_header(const std::string& lower_headers, const std::string& name) {
  const std::size_t at = lower_headers.find("\n" + name);
  return at == std::string::npos ? at : at + 1 + name.size();
}

// What the bytes received so far say about the request they begin.
struct RequestShape {
  enum class State { HeadersIncomplete, HeadersComplete, HeadersTooLarge, Chunked, BodyTooLarge } state;
  std::size_t total = 0;          // HeadersComplete: header and body bytes together
  bool expects_continue = false;  // the client waits for `100 Continue` before sending the body
};

RequestShape request_shape(const std::string& received, std::size_t max_body_bytes) {
  using State = RequestShape::State;
  std::size_t end = received.find("\r\n\r\n"), separator = 4;
  if (const std::size_t bare = received.find("\n\n"); bare < end) end = bare, separator = 2;
  if (end == std::string::npos)
    return {received.size() > kMaxHeaderBytes ? State::HeadersTooLarge : State::HeadersIncomplete};
  if (end > kMaxHeaderBytes) return {State::HeadersTooLarge};
  std::string headers = received.substr(0, end);
  for (char& ch : headers) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (find_header(headers, "transfer-encoding:") != std::string::npos) return {State::Chunked};
  RequestShape shape{State::HeadersComplete, end + separator};
  shape.expects_continue = find_header(headers, "expect:") != std::string::npos;
  if (std::size_t at = find_header(headers, "content-length:"); at != std::string::npos) {
    while (at < headers.size() && (headers[at] == ' ' || headers[at] == '\t')) ++at;
    // A malformed length is httplib's to refuse (400): the request goes on as it is.
    std::size_t length = 0;
    for (; at < headers.size() && std::isdigit(static_cast<unsigned char>(headers[at])); ++at) {
      length = length * 10 + std::size_t(headers[at] - '0');
      if (length > max_body_bytes) return {State::BodyTooLarge};
    }
    shape.total += length;
  }
  return shape;
}

std::string reason_phrase(int status) {
  switch (status) {
    case 408: return "Request Timeout";
    case 411: return "Length Required";
    case 413: return "Payload Too Large";
    case 431: return "Request Header Fields Too Large";
    case 503: return "Service Unavailable";
    default: return "Error";
  }
}

// The whole HTTP response for a refusal the waiting room answers itself, with the API's JSON error.
std::string refusal(int status, const std::string& message, const std::string& field, const std::string& kind,
                    int retry_after_s = 0) {
  const ApiResponse e = error_response(status, message, field, kind);
  std::string head = "HTTP/1.1 " + std::to_string(status) + " " + reason_phrase(status) + "\r\nContent-Type: " + e.content_type +
                     "\r\nContent-Length: " + std::to_string(e.body.size()) +
                     "\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nConnection: close\r\n";
  if (retry_after_s > 0) head += "Retry-After: " + std::to_string(retry_after_s) + "\r\n";
  return head + "\r\n" + e.body;
}

}  // namespace

struct ConnectionFront::Impl {
  ConnectionLimits limits;
  std::size_t max_body_bytes;
  SSL_CTX* tls;
  RequestProcessor process;
  httplib::ThreadPool workers;
  int wake_fd = -1;  // an eventfd: admit() and workers wake the waiting room with it

  std::mutex mutex;  // guards the members below up to `stopped`
  std::vector<std::unique_ptr<Connection>> arrivals;  // new or handed back, for the waiting room to take
  std::unordered_map<std::string, int> per_address;   // open connections by client group (client_group.h)
  int open = 0;
  std::uint64_t accepted = 0;  // sockets handed to admit() so far, admitted or not
  std::size_t body_budget_used = 0;      // of kSharedBodyBudget, by requests being received
  std::size_t response_budget_used = 0;  // of kSharedResponseBudget, by responses being sent
  bool stopping = false, stopped = false;

  std::vector<std::unique_ptr<Connection>> waiting;  // the waiting room's own, touched by its thread only
  std::thread waiting_room;

  Impl(const ConnectionLimits& l, std::size_t max_body, int threads, SSL_CTX* t, RequestProcessor p)
      : limits(l), max_body_bytes(max_body), tls(t), process(std::move(p)), workers(std::size_t(std::max(1, threads))) {
    wake_fd = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    waiting_room = std::thread([this] { run_waiting_room(); });
  }

  void wake() const {
    const std::uint64_t one = 1;
    [[maybe_unused]] const ssize_t n = ::write(wake_fd, &one, sizeof one);
  }

  // ---- Admission (the accept thread) ----

  void admit(int socket) {
    auto c = std::make_unique<Connection>();
    c->socket = socket;
    sockaddr_storage a{};
    socklen_t length = sizeof a;
    if (::getpeername(socket, reinterpret_cast<sockaddr*>(&a), &length) == 0) numeric_address(a, length, c->address, c->port);
    c->group = client_group(c->address);
    length = sizeof a;
    if (::getsockname(socket, reinterpret_cast<sockaddr*>(&a), &length) == 0)
      numeric_address(a, length, c->local_address, c->local_port);
    {
      std::lock_guard<std::mutex> lock(mutex);
      ++accepted;
      int& from_address = per_address[c->group];
      // Beyond twice the cap (or the total) not even a refusal is worth a socket.
      const bool beyond_total = open >= limits.max_total &&
                                (open >= limits.max_total + kAdmittedBeyondTotal || from_address >= kMostOpenToGoBeyondTotal);
      if (stopping || beyond_total || from_address >= 2 * limits.max_per_address) {
        if (from_address == 0) per_address.erase(c->group);
        return;  // ~Connection closes the socket
      }
      ++from_address;
      ++open;
      c->refused = from_address > limits.max_per_address;
    }
    c->waiting_since = Clock::now();
    ::fcntl(socket, F_SETFL, ::fcntl(socket, F_GETFL) | O_NONBLOCK);
    const int yes = 1;  // responses are written as headers then body: do not hold the body back
    ::setsockopt(socket, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
    if (tls) {
      c->tls = SSL_new(tls);
      if (!c->tls || SSL_set_fd(c->tls, socket) != 1) return release(std::move(c));
      SSL_set_mode(c->tls, SSL_MODE_ENABLE_PARTIAL_WRITE | SSL_MODE_ACCEPT_MOVING_WRITE_BUFFER);
      SSL_set_accept_state(c->tls);
      c->phase = Connection::Phase::Handshake;
      c->deadline = after(limits.tls_handshake_s);
    } else {
      c->deadline = after(limits.idle_timeout_s);
    }
    to_waiting_room(std::move(c));
  }

  void to_waiting_room(std::unique_ptr<Connection> c) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (stopping) return release_locked(std::move(c));
      arrivals.push_back(std::move(c));
    }
    wake();
  }

  void release(std::unique_ptr<Connection> c) {
    std::lock_guard<std::mutex> lock(mutex);
    release_locked(std::move(c));
  }
  void release_locked(std::unique_ptr<Connection> c) {
    unreserve_body_locked(*c);
    response_budget_used -= c->outgoing_reserved;
    if (auto it = per_address.find(c->group); it != per_address.end() && --it->second <= 0) per_address.erase(it);
    --open;
  }

  // ---- The waiting room (its own thread) ----

  void run_waiting_room() {
    std::vector<pollfd> polled;
    for (;;) {
      std::vector<std::unique_ptr<Connection>> arrived;
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (stopping) break;
        arrived.swap(arrivals);
      }
      // A connection handed back may hold a pipelined request, or TLS data already decrypted
      // that poll() cannot see: look at every arrival once before waiting.
      for (auto& c : arrived)
        if (advance(c)) waiting.push_back(std::move(c));
      polled.assign(1, pollfd{wake_fd, POLLIN, 0});
      Clock::time_point next = Clock::time_point::max();
      for (const auto& c : waiting) {
        const short events = c->phase == Connection::Phase::Sending ? c->send_events : c->tls_wants_write ? POLLOUT : POLLIN;
        polled.push_back(pollfd{c->socket, events, 0});
        next = std::min(next, c->deadline);
      }
      if (::poll(polled.data(), polled.size(), next == Clock::time_point::max() ? -1 : ms_until(next)) < 0) {
        if (errno != EINTR) std::this_thread::sleep_for(std::chrono::milliseconds(10));  // e.g. ENOMEM: try again
        continue;
      }
      if (polled[0].revents) {
        std::uint64_t count;
        [[maybe_unused]] const ssize_t n = ::read(wake_fd, &count, sizeof count);
      }
      const auto now = Clock::now();
      for (std::size_t i = 0; i + 1 < polled.size(); ++i) {
        auto& c = waiting[i];
        if (polled[i + 1].revents && !advance(c)) continue;  // it left; `c` is empty
        // Checked also when bytes came: a client dribbling fast still has only its deadline.
        if (now >= c->deadline) expire(std::move(c));
      }
      waiting.erase(std::remove(waiting.begin(), waiting.end(), nullptr), waiting.end());
      evict_beyond_total();
    }
    for (auto& c : waiting) release(std::move(c));
    waiting.clear();
  }

  // While more than max_total are open, closes waiting connections of the address that has the
  // most open, the longest-waiting first: a flood spread over a few dozen addresses loses its own
  // connections before a client with one or two does.
  void evict_beyond_total() {
    std::lock_guard<std::mutex> lock(mutex);
    while (open > limits.max_total && !waiting.empty()) {
      auto victim = waiting.begin();
      for (auto it = waiting.begin(); it != waiting.end(); ++it) {
        const int mine = per_address[(*it)->group], theirs = per_address[(*victim)->group];
        if (mine > theirs || (mine == theirs && (*it)->waiting_since < (*victim)->waiting_since)) victim = it;
      }
      release_locked(std::move(*victim));
      waiting.erase(victim);
    }
  }

  // Moves a connection on as far as its bytes allow. False when it left the waiting room
  // (handed to a worker or closed; `c` is then empty).
  bool advance(std::unique_ptr<Connection>& c) {
    switch (c->phase) {
      case Connection::Phase::Draining:
        return drain(*c) || (release(std::move(c)), false);
      case Connection::Phase::Sending:
        if (!send_some(*c)) return release(std::move(c)), false;
        if (c->sent < c->outgoing.size()) return true;
        c = response_sent(std::move(c));
        if (!c) return false;
        break;  // a pipelined request may be waiting
      case Connection::Phase::Handshake:
        if (!shake_hands(*c)) return release(std::move(c)), false;
        if (c->phase == Connection::Phase::Handshake) return true;
        break;
      default: break;
    }
    // Over its address's cap: answered at once, without waiting for a request that may never come.
    if (c->refused)
      return refuse(*c, refusal(503,
                                "too many open connections from " + c->group + " (at most " +
                                    std::to_string(limits.max_per_address) + "); close idle ones or retry later",
                                "", "too_many_connections", kRetryAfterSeconds));
    receive_available(*c);
    if (c->phase == Connection::Phase::Idle && !c->received.empty()) c->start_request(limits.request_deadline_s);
    if (c->phase == Connection::Phase::Idle) return !c->peer_closed || (release(std::move(c)), false);
    return take_request(c);
  }

  // False when the handshake failed; the phase becomes Idle once it is done.
  bool shake_hands(Connection& c) {
    const int r = SSL_accept(c.tls);
    if (r != 1) {
      const int e = SSL_get_error(c.tls, r);
      c.tls_wants_write = e == SSL_ERROR_WANT_WRITE;
      return e == SSL_ERROR_WANT_READ || e == SSL_ERROR_WANT_WRITE;
    }
    c.tls_wants_write = false;
    c.phase = Connection::Phase::Idle;
    c.deadline = after(limits.idle_timeout_s);
    return true;
  }

  // A request is being received: hand it to a worker once it is whole, refuse it, or wait.
  bool take_request(std::unique_ptr<Connection>& c) {
    using State = RequestShape::State;
    const RequestShape shape = request_shape(c->received, max_body_bytes);
    switch (shape.state) {
      case State::HeadersTooLarge:
        return refuse(*c, refusal(431, "the request headers are larger than " + std::to_string(kMaxHeaderBytes) + " bytes",
                                  "headers", "headers_too_large"));
      case State::Chunked:
        return refuse(*c, refusal(411, "send the body with a Content-Length (chunked request bodies are not accepted)",
                                  "body", "length_required"));
      case State::BodyTooLarge:
        return refuse(*c, refusal(413, "the request body is too large", "body", "payload_too_large"));
      case State::HeadersIncomplete: break;
      case State::HeadersComplete:
        if (c->received.size() >= shape.total) {
          dispatch(std::move(c));
          return false;
        }
        if (shape.total > c->receive_limit && !reserve_body(*c, shape.total))
          return refuse(*c, refusal(503, "the server is receiving too many large requests; retry later", "body",
                                    "server_busy", kRetryAfterSeconds));
        if (shape.expects_continue && !c->continue_sent) {
          static const std::string kContinue = "HTTP/1.1 100 Continue\r\n\r\n";
          std::size_t n = 0;
          short events = 0;
          write_some(*c, kContinue.data(), kContinue.size(), n, events);
          c->continue_sent = true;
        }
        break;
    }
    return !c->peer_closed || (release(std::move(c)), false);
  }

  // Lets `c` receive a body of `total` request bytes in all, from the shared budget.
  bool reserve_body(Connection& c, std::size_t total) {
    std::lock_guard<std::mutex> lock(mutex);
    const std::size_t extra = total - kBufferPerConnection;
    if (body_budget_used + extra > kSharedBodyBudget) return false;
    body_budget_used += extra;
    c.reserved = extra;
    c.receive_limit = total;
    return true;
  }
  void unreserve_body_locked(Connection& c) {
    body_budget_used -= c.reserved;
    c.reserved = 0;
    c.receive_limit = kBufferPerConnection;
  }

  // Reads what has arrived, up to what the request may hold.
  void receive_available(Connection& c) {
    char buffer[16 * 1024];
    while (c.received.size() < c.receive_limit) {
      std::size_t n = 0;
      short events = 0;
      const Transfer t = read_some(c, buffer, std::min(sizeof buffer, c.receive_limit - c.received.size()), n, events);
      if (t == Transfer::WouldBlock) {
        c.tls_wants_write = events == POLLOUT;  // TLS may need to write before it can read
        return;
      }
      if (t == Transfer::Failed || n == 0) {
        c.peer_closed = true;
        return;
      }
      c.received.append(buffer, n);
    }
  }

  // A deadline passed: a request started and not finished gets 408; others just close.
  void expire(std::unique_ptr<Connection> c) {
    if (c->phase == Connection::Phase::Receiving &&
        refuse(*c, refusal(408, "the request did not arrive within " + seconds(limits.request_deadline_s) + " s of its first byte",
                           "", "request_timeout")))
      return waiting.push_back(std::move(c));  // now draining (the loop skips it this round)
    release(std::move(c));
  }

  static std::string seconds(double s) {
    std::string text = std::to_string(s);
    text.erase(text.find_last_not_of('0') + 1);
    if (text.back() == '.') text.pop_back();
    return text;
  }

  // Sends a refusal (best effort, never waiting: a few hundred bytes, which a socket takes at
  // once) and ends the sending side; the connection then drains. Returns true: it stays.
  bool refuse(Connection& c, const std::string& response) {
    std::size_t n = 0;
    short events = 0;
    write_some(c, response.data(), response.size(), n, events);
    if (c.tls) SSL_shutdown(c.tls);
    ::shutdown(c.socket, SHUT_WR);
    {
      std::lock_guard<std::mutex> lock(mutex);
      unreserve_body_locked(c);
    }
    c.received.clear();
    c.received.shrink_to_fit();
    c.phase = Connection::Phase::Draining;
    c.tls_wants_write = false;
    c.deadline = after(kDrainSeconds);
    return true;
  }

  // Reads and drops whatever the client still sends after a refusal. False once it has closed.
  static bool drain(Connection& c) {
    char buffer[16 * 1024];
    for (;;) {
      const ssize_t n = ::recv(c.socket, buffer, sizeof buffer, MSG_DONTWAIT);
      if (n > 0) continue;
      return n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR);
    }
  }

  // ---- Workers ----

  void dispatch(std::unique_ptr<Connection> c) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      unreserve_body_locked(*c);  // the budget bounds the waiting room; workers are few
    }
    c->continue_sent = false;
    Connection* raw = c.release();  // std::function needs a copyable job; the job owns it again
    workers.enqueue([this, raw] { serve(std::unique_ptr<Connection>(raw)); });
  }

  void serve(std::unique_ptr<Connection> c) {
    ConnectionStream stream(*c);
    bool stopping_now;
    {
      std::lock_guard<std::mutex> lock(mutex);
      stopping_now = stopping;
    }
    const bool close = stopping_now || c->peer_closed || c->requests_served + 1 >= limits.max_requests_per_connection;
    bool closed_by_client = false;
    const bool ok = process(stream, close, closed_by_client);
    stream.forget_consumed();
    ++c->requests_served;
    c->close_after_sending = !ok || close || closed_by_client;
    c->deadline = after(limits.response_deadline_s);
    // What the socket takes at once is sent now; the rest waits in the waiting room if the
    // budget allows, else this worker sends it (bounded by the response deadline).
    if (!send_some(*c)) return release(std::move(c));
    if (c->sent < c->outgoing.size()) {
      if (reserve_response(*c)) {
        c->phase = Connection::Phase::Sending;
        return to_waiting_room(std::move(c));
      }
      while (c->sent < c->outgoing.size())
        if (!wait_for(c->socket, c->send_events, c->deadline) || !send_some(*c)) return release(std::move(c));
    }
    if (auto next = response_sent(std::move(c))) to_waiting_room(std::move(next));
  }

  // Sends what the socket takes now; false when the connection failed.
  static bool send_some(Connection& c) {
    while (c.sent < c.outgoing.size()) {
      std::size_t n = 0;
      const Transfer t = write_some(c, c.outgoing.data() + c.sent, c.outgoing.size() - c.sent, n, c.send_events);
      if (t == Transfer::Failed) return false;
      if (t == Transfer::WouldBlock) return true;
      c.sent += n;
    }
    return true;
  }

  bool reserve_response(Connection& c) {
    std::lock_guard<std::mutex> lock(mutex);
    if (response_budget_used + c.outgoing.size() > kSharedResponseBudget) return false;
    response_budget_used += c.outgoing.size();
    c.outgoing_reserved = c.outgoing.size();
    return true;
  }

  // The response is out: the connection closes, or waits for its next request (returned).
  std::unique_ptr<Connection> response_sent(std::unique_ptr<Connection> c) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      response_budget_used -= c->outgoing_reserved;
      c->outgoing_reserved = 0;
    }
    c->outgoing.clear();
    c->outgoing.shrink_to_fit();
    c->sent = 0;
    if (c->close_after_sending) {
      release(std::move(c));
      return nullptr;
    }
    c->phase = Connection::Phase::Idle;
    c->deadline = after(limits.idle_timeout_s);
    c->waiting_since = Clock::now();
    return c;
  }

  void stop() {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (stopped) return;
      stopping = stopped = true;
      for (auto& c : arrivals) release_locked(std::move(c));
      arrivals.clear();
    }
    wake();
    waiting_room.join();
    workers.shutdown();  // requests in progress finish; their connections close
    ::close(wake_fd);
  }
};

ConnectionFront::ConnectionFront(const ConnectionLimits& limits, std::size_t max_body_bytes, int worker_threads, ssl_ctx_st* tls,
                                 RequestProcessor process)
    : impl_(std::make_unique<Impl>(limits, max_body_bytes, worker_threads, tls, std::move(process))) {}

ConnectionFront::~ConnectionFront() { impl_->stop(); }

void ConnectionFront::admit(int socket) { impl_->admit(socket); }

void ConnectionFront::stop() { impl_->stop(); }

int ConnectionFront::open_connections() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->open;
}

std::uint64_t ConnectionFront::accepted_connections() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->accepted;
}

}  // namespace caliper::server
