#include "scripting/net_open.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace mcemu::scripting {

namespace {

struct Address {
  sockaddr_storage storage{};
  socklen_t size = 0;
  int family = AF_UNSPEC;
};

// A numeric address and port, or family AF_UNSPEC.
Address address_of(const std::string& host, std::uint16_t port) {
  Address a;
  auto* v4 = reinterpret_cast<sockaddr_in*>(&a.storage);
  auto* v6 = reinterpret_cast<sockaddr_in6*>(&a.storage);
  if (inet_pton(AF_INET, host.c_str(), &v4->sin_addr) == 1) {
    v4->sin_family = AF_INET;
    v4->sin_port = htons(port);
    a.size = sizeof *v4;
    a.family = AF_INET;
  } else if (inet_pton(AF_INET6, host.c_str(), &v6->sin6_addr) == 1) {
    v6->sin6_family = AF_INET6;
    v6->sin6_port = htons(port);
    a.size = sizeof *v6;
    a.family = AF_INET6;
  }
  return a;
}

NetOpened fail(int fd, int error) {
  if (fd >= 0) close(fd);
  return NetOpened{-1, error};
}

}  // namespace

bool numeric_host(const std::string& host) { return address_of(host, 0).family != AF_UNSPEC; }

NetOpened open_net(const ipc::NetRequest& request, const std::string& bind_address, const std::string& peer) {
  using Kind = ipc::NetRequest::Kind;
  if (request.kind == Kind::client) {
    const Address to = address_of(peer, request.port);
    if (to.family == AF_UNSPEC) return NetOpened{-1, EHOSTUNREACH};  // the name did not resolve
    const int fd = socket(to.family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) return fail(-1, errno);
    if (connect(fd, reinterpret_cast<const sockaddr*>(&to.storage), to.size) == 0) return NetOpened{fd, 0};
    if (errno == EINPROGRESS || errno == EAGAIN) return NetOpened{fd, EINPROGRESS};
    return fail(fd, errno);
  }
  const Address local = address_of(bind_address, request.port);
  if (local.family == AF_UNSPEC) return NetOpened{-1, EADDRNOTAVAIL};
  const bool udp = request.kind == Kind::udp;
  const int fd = socket(local.family, (udp ? SOCK_DGRAM : SOCK_STREAM) | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return fail(-1, errno);
  const int one = 1;
  setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (bind(fd, reinterpret_cast<const sockaddr*>(&local.storage), local.size) != 0) return fail(fd, errno);
  if (!udp && listen(fd, 4) != 0) return fail(fd, errno);
  return NetOpened{fd, 0};
}

}  // namespace mcemu::scripting
