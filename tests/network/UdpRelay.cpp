// udp-relay: the network between the test's namespaces (NetworkBenchTest).
// The kernel here has no netem qdisc, so delay, jitter, loss and outages
// are made in user space: every console and the rover see each other only
// at public addresses held by the relay, which forwards each datagram to
// the real address after the profile's delay, or drops it.
//
//   udp-relay --path A_REAL,A_PUBLIC,B_PUBLIC,B_REAL [--path ...]
//             --ports 7400-7440 --delay-ms 50 --jitter-ms 20 --loss 0.05
//             --seed 1 --duration 600
//
// A datagram from A_REAL to B_PUBLIC:P leaves from A_PUBLIC:P for B_REAL:P,
// and the other way round. SIGUSR1 starts an outage (everything dropped),
// SIGUSR2 ends it. On SIGTERM or after --duration it prints one JSON line
// of counts and exits.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <map>
#include <queue>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

std::atomic<bool> g_stop{false}, g_outage{false};

struct Path {
  in_addr_t a_real, a_public, b_public, b_real;
};

struct Options {
  std::vector<Path> paths;
  int first_port = 7400, last_port = 7440;
  double delay_ms = 0.0, jitter_ms = 0.0, loss = 0.0, duration_s = 600.0;
  unsigned seed = 1;
};

in_addr_t address(const std::string& text) {
  in_addr a{};
  if (inet_pton(AF_INET, text.c_str(), &a) != 1) throw std::invalid_argument("bad address " + text);
  return a.s_addr;
}

std::vector<std::string> split(const std::string& text, char by) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, by);) parts.push_back(part);
  return parts;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "--path") {
      const auto p = split(value, ',');
      if (p.size() != 4) throw std::invalid_argument("--path takes 4 addresses");
      o.paths.push_back({address(p[0]), address(p[1]), address(p[2]), address(p[3])});
    } else if (flag == "--ports") {
      const auto p = split(value, '-');
      if (p.size() != 2) throw std::invalid_argument("--ports takes FIRST-LAST");
      o.first_port = std::stoi(p[0]), o.last_port = std::stoi(p[1]);
    } else if (flag == "--delay-ms") {
      o.delay_ms = std::stod(value);
    } else if (flag == "--jitter-ms") {
      o.jitter_ms = std::stod(value);
    } else if (flag == "--loss") {
      o.loss = std::stod(value);
    } else if (flag == "--seed") {
      o.seed = unsigned(std::stoul(value));
    } else if (flag == "--duration") {
      o.duration_s = std::stod(value);
    } else {
      throw std::invalid_argument("unknown option " + flag);
    }
  }
  if (o.paths.empty() || o.first_port > o.last_port)
    throw std::invalid_argument("at least one --path and a port range are needed");
  return o;
}

struct Datagram {
  Clock::time_point release;
  std::uint64_t order;
  int socket;
  sockaddr_in to;
  std::vector<char> bytes;
  bool operator>(const Datagram& other) const {
    return release != other.release ? release > other.release : order > other.order;
  }
};

class Relay {
 public:
  explicit Relay(Options options) : o_(std::move(options)), random_(o_.seed) {
    for (const auto& p : o_.paths)
      for (const in_addr_t a : {p.a_public, p.b_public})
        for (int port = o_.first_port; port <= o_.last_port; ++port) bindOnce(a, port);
  }

  void run() {
    const auto end = Clock::now() + std::chrono::duration<double>(o_.duration_s);
    std::vector<char> buffer(65536);
    while (!g_stop && Clock::now() < end) {
      int timeout_ms = 50;
      if (!queue_.empty())
        timeout_ms = int(std::clamp<long>(std::chrono::duration_cast<std::chrono::milliseconds>(
                                              queue_.top().release - Clock::now())
                                              .count(),
                                          0L, 50L));
      if (::poll(polls_.data(), polls_.size(), timeout_ms) > 0)
        for (const auto& p : polls_)
          if (p.revents & POLLIN) receive(p.fd, buffer);
      release();
    }
    std::cout << "{\"relay\": \"stopped\", \"forwarded\": " << forwarded_ << ", \"lost\": " << lost_
              << ", \"outage_dropped\": " << outage_dropped_ << ", \"unroutable\": " << unroutable_
              << "}" << std::endl;
  }

 private:
  void bindOnce(in_addr_t a, int port) {
    if (sockets_.count({a, port})) return;
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in at{};
    at.sin_family = AF_INET, at.sin_port = htons(std::uint16_t(port)), at.sin_addr.s_addr = a;
    if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&at), sizeof at) != 0)
      throw std::runtime_error("cannot bind " + std::string(inet_ntoa(at.sin_addr)) + ":" +
                               std::to_string(port) + ": " + std::strerror(errno));
    sockets_[{a, port}] = fd;
    where_[fd] = {a, port};
    polls_.push_back({fd, POLLIN, 0});
  }

  void receive(int fd, std::vector<char>& buffer) {
    sockaddr_in from{};
    socklen_t length = sizeof from;
    const auto n = ::recvfrom(fd, buffer.data(), buffer.size(), MSG_DONTWAIT,
                              reinterpret_cast<sockaddr*>(&from), &length);
    if (n <= 0) return;
    const auto [at, port] = where_[fd];
    for (const auto& p : o_.paths) {
      const in_addr_t src = from.sin_addr.s_addr;
      if (src == p.a_real && at == p.b_public)
        return forward(p.a_public, port, p.b_real, buffer, n);
      if (src == p.b_real && at == p.a_public)
        return forward(p.b_public, port, p.a_real, buffer, n);
    }
    ++unroutable_;
  }

  void forward(in_addr_t via, int port, in_addr_t to, const std::vector<char>& buffer, long n) {
    if (g_outage) return void(++outage_dropped_);
    if (std::uniform_real_distribution<double>(0, 1)(random_) < o_.loss) return void(++lost_);
    const double jitter = std::uniform_real_distribution<double>(-1, 1)(random_) * o_.jitter_ms;
    const double delay_ms = std::max(0.0, o_.delay_ms + jitter);
    Datagram d{Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                  std::chrono::duration<double, std::milli>(delay_ms)),
               order_++,
               sockets_.at({via, port}),
               {},
               {buffer.begin(), buffer.begin() + n}};
    d.to.sin_family = AF_INET, d.to.sin_port = htons(std::uint16_t(port)),
    d.to.sin_addr.s_addr = to;
    queue_.push(std::move(d));
  }

  void release() {
    while (!queue_.empty() && queue_.top().release <= Clock::now()) {
      const auto& d = queue_.top();
      if (g_outage)
        ++outage_dropped_;
      else if (::sendto(d.socket, d.bytes.data(), d.bytes.size(), 0,
                        reinterpret_cast<const sockaddr*>(&d.to), sizeof d.to) >= 0)
        ++forwarded_;
      queue_.pop();
    }
  }

  Options o_;
  std::mt19937_64 random_;
  std::map<std::pair<in_addr_t, int>, int> sockets_;
  std::map<int, std::pair<in_addr_t, int>> where_;
  std::vector<pollfd> polls_;
  std::priority_queue<Datagram, std::vector<Datagram>, std::greater<>> queue_;
  std::uint64_t order_ = 0;
  long forwarded_ = 0, lost_ = 0, outage_dropped_ = 0, unroutable_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGTERM, [](int) { g_stop = true; });
  std::signal(SIGINT, [](int) { g_stop = true; });
  std::signal(SIGUSR1, [](int) { g_outage = true; });
  std::signal(SIGUSR2, [](int) { g_outage = false; });
  try {
    Relay relay(parse(argc, argv));
    std::cout << "{\"relay\": \"ready\"}" << std::endl;
    relay.run();
  } catch (const std::exception& e) {
    std::cerr << "udp-relay: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}
