#include "protocols/line/net/pty_server.hpp"

#include <fcntl.h>
#include <poll.h>
#include <spdlog/spdlog.h>
#include <termios.h>
#include <unistd.h>

#include <boost/asio/posix/stream_descriptor.hpp>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace mcemu::line::net {

namespace asio = boost::asio;

// The master side as LineConnection's stream: a stream descriptor whose shutdown does nothing (a
// pty has no half-close; the connection ends when the program closes the subordinate side).
class PtyServer::Stream {
 public:
  explicit Stream(asio::posix::stream_descriptor d) : d_(std::move(d)) {}
  using executor_type = asio::posix::stream_descriptor::executor_type;
  executor_type get_executor() { return d_.get_executor(); }
  template <class Buffers, class Handler>
  void async_read_some(const Buffers& b, Handler&& h) {
    d_.async_read_some(b, std::forward<Handler>(h));
  }
  template <class Buffers, class Handler>
  void async_write_some(const Buffers& b, Handler&& h) {
    d_.async_write_some(b, std::forward<Handler>(h));
  }
  template <class Buffers>
  std::size_t write_some(const Buffers& b, boost::system::error_code& ec) {
    return d_.write_some(b, ec);
  }
  void non_blocking(bool on, boost::system::error_code& ec) { d_.non_blocking(on, ec); }
  void shutdown(asio::socket_base::shutdown_type, boost::system::error_code& ec) { ec = {}; }
  void close(boost::system::error_code& ec) { d_.close(ec); }

 private:
  asio::posix::stream_descriptor d_;
};

namespace {

[[noreturn]] void fail(const PtyOptions& o, const std::string& what) {
  throw std::runtime_error("cannot create the pseudo-terminal " + o.link_path + " for " + o.line.name + " (" + what +
                           "); choose another path with " + o.flag);
}

std::string errno_text() { return std::strerror(errno); }

}  // namespace

PtyServer::PtyServer(asio::io_context& io, PtyOptions options, SessionFactory factory)
    : io_(io), options_(std::move(options)), factory_(std::move(factory)), timer_(io) {
  master_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (master_ < 0) fail(options_, "posix_openpt: " + errno_text());
  if (::grantpt(master_) != 0 || ::unlockpt(master_) != 0) {
    const auto e = errno_text();
    ::close(master_);
    fail(options_, "grantpt/unlockpt: " + e);
  }
  char name[128];
  if (::ptsname_r(master_, name, sizeof name) != 0) {
    const auto e = errno_text();
    ::close(master_);
    fail(options_, "ptsname: " + e);
  }
  subordinate_ = name;
  // Open and close the subordinate side once: until it has been closed, Linux reports no hang-up on
  // the master, and the first check() would take "nobody there" for a program.
  if (const int sub = ::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC); sub >= 0) ::close(sub);
  // Raw bytes both ways: no echo, no line editing, no CR/LF translation (faulhaber.md §2.2).
  termios t{};
  if (::tcgetattr(master_, &t) == 0) {
    ::cfmakeraw(&t);
    ::tcsetattr(master_, TCSANOW, &t);
  }
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path link(options_.link_path);
  const auto st = fs::symlink_status(link, ec);
  if (!ec && fs::exists(st)) {
    if (!fs::is_symlink(st)) {
      ::close(master_);
      fail(options_, "the path exists and is not a symbolic link");
    }
    fs::remove(link, ec);
  }
  fs::create_symlink(subordinate_, link, ec);
  if (ec) {
    ::close(master_);
    fail(options_, ec.message());
  }
  link_created_ = true;
}

PtyServer::~PtyServer() {
  stop();
  if (link_created_) {
    std::error_code ec;
    const auto target = std::filesystem::read_symlink(options_.link_path, ec);
    if (!ec && target == subordinate_) std::filesystem::remove(options_.link_path, ec);
  }
  if (master_ >= 0) ::close(master_);
}

void PtyServer::start() {
  if (running_) return;
  running_ = true;
  check();
}

void PtyServer::stop() {
  running_ = false;
  timer_.cancel();
  close_connections();
}

void PtyServer::close_connections() {
  if (auto c = connection_) c->close();  // on_closed forgets it
}

void PtyServer::arm() {
  if (!running_ || connection_) return;
  timer_.expires_after(options_.poll);
  timer_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec) check();
  });
}

// A program has the subordinate side open when the master reports no hang-up.
void PtyServer::check() {
  if (!running_ || connection_) return;
  pollfd p{master_, POLLIN, 0};
  const int n = ::poll(&p, 1, 0);
  if (n < 0 || (p.revents & POLLHUP) != 0) return arm();
  const int fd = ::fcntl(master_, F_DUPFD_CLOEXEC, 0);
  if (fd < 0) {
    spdlog::warn("{} pty {}: dup: {}", options_.line.name, options_.link_path, errno_text());
    return arm();
  }
  PeerInfo peer{"pty " + options_.link_path, next_id_++};
  spdlog::info("{} pty {}: a program opened {}", options_.line.name, options_.link_path, subordinate_);
  auto conn = std::make_shared<LineConnection<Stream>>(Stream(asio::posix::stream_descriptor(io_, fd)), options_.line,
                                                       peer, [this](LineConnectionBase* c) { on_closed(c); });
  connection_ = conn;
  conn->start(factory_(peer));
}

void PtyServer::on_closed(LineConnectionBase* c) {
  if (connection_.get() != c) return;
  connection_.reset();
  if (running_) spdlog::info("{} pty {}: closed by the program", options_.line.name, options_.link_path);
  arm();
}

}  // namespace mcemu::line::net
