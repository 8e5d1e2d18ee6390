// The one thing HttpServer needs of each of its connections (an HTTP session or a WebSocket) to
// keep the connection limit and to end them all at stop(). Internal to web/net.
#pragma once

namespace mcemu::web::net {

class Connection {
 public:
  virtual ~Connection() = default;
  // Closes the socket at once; pending handlers become no-ops. Idempotent.
  virtual void close() = 0;
};

}  // namespace mcemu::web::net
