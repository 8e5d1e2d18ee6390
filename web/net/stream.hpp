// The stream types of web/net's connections: Beast's basic_stream on the io_context's own executor
// type instead of tcp_stream's type-erased any_io_executor (issue 26: at 8 connections, copying and
// destroying the erased executor for every read, write and timer took ~6 % of the server's user
// time per request). The acceptor hands out sockets of the same executor type. Internal to web/net.
#pragma once

#include <boost/asio/basic_socket_acceptor.hpp>
#include <boost/asio/basic_stream_socket.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/basic_stream.hpp>
#include <boost/beast/core/rate_policy.hpp>

namespace mcemu::web::net {

using Executor = boost::asio::io_context::executor_type;
using Acceptor = boost::asio::basic_socket_acceptor<boost::asio::ip::tcp, Executor>;
using Socket = boost::asio::basic_stream_socket<boost::asio::ip::tcp, Executor>;
using Stream = boost::beast::basic_stream<boost::asio::ip::tcp, Executor, boost::beast::unlimited_rate_policy>;

}  // namespace mcemu::web::net
