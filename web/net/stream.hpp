// The stream types of web/net's connections: Beast's basic_stream over the servers' TCP socket type
// (protocols/line/net/tcp_types.hpp: the io_context's own executor type, not the type-erased
// any_io_executor of beast::tcp_stream). Internal to web/net.
#pragma once

#include <boost/beast/core/basic_stream.hpp>
#include <boost/beast/core/rate_policy.hpp>

#include "protocols/line/net/tcp_types.hpp"

namespace mcemu::web::net {

using Acceptor = line::net::TcpAcceptor;
using Socket = line::net::TcpSocket;
using Stream =
    boost::beast::basic_stream<boost::asio::ip::tcp, line::net::TcpExecutor, boost::beast::unlimited_rate_policy>;

}  // namespace mcemu::web::net
