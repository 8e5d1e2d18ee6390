// The TCP socket and acceptor types of mcemu's servers (the line services here, HTTP and WebSocket
// in web/net/stream.hpp): on the io_context's own executor type instead of Asio's default, the
// type-erased any_io_executor, which every asynchronous read, write and wait copies and destroys
// (issue 26: ~6 % of the HTTP server's user time per request at 8 connections).
#pragma once

#include <boost/asio/basic_socket_acceptor.hpp>
#include <boost/asio/basic_stream_socket.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

namespace mcemu::line::net {

using TcpExecutor = boost::asio::io_context::executor_type;
using TcpSocket = boost::asio::basic_stream_socket<boost::asio::ip::tcp, TcpExecutor>;
using TcpAcceptor = boost::asio::basic_socket_acceptor<boost::asio::ip::tcp, TcpExecutor>;

}  // namespace mcemu::line::net
