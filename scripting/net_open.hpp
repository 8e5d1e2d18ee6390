// The sockets of a script's mcnet objects (scripting.md §7), opened by mcemu in its own network
// namespace: the sandboxed script process has no network and may not create sockets; it receives
// the descriptor over the socketpair (SCM_RIGHTS) and serves it as before (accept, send, recv).
// Server and UDP sockets bind to the drive's --bind address (never one the script names) with
// SO_REUSEADDR; a client socket's non-blocking connect is started here. mcemu closes its own copy
// right after handing it over, so the kernel still closes the socket when the script dies.
#pragma once

#include <string>

#include "scripting/core/ipc.hpp"

namespace mcemu::scripting {

struct NetOpened {
  int fd = -1;    // the socket (the caller closes it after sending), or -1
  int error = 0;  // 0 / EINPROGRESS (client) with fd; otherwise the errno and no fd
};

// `peer` is the numeric address of the client's or UDP peer's host (already resolved), ignored for
// a server. A UDP peer whose name did not resolve still gets its socket (its sends then fail).
NetOpened open_net(const ipc::NetRequest& request, const std::string& bind_address, const std::string& peer);

// True when `host` is a numeric IPv4 or IPv6 address (needs no resolution).
bool numeric_host(const std::string& host);

}  // namespace mcemu::scripting
