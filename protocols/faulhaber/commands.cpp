#include "protocols/faulhaber/commands.hpp"

#include <algorithm>
#include <array>

namespace mcemu::faulhaber {

namespace {

constexpr std::uint16_t k_controlword = 0x6040;

struct Call {
  od::ObjectDictionary& od;
  const FrameView& request;
  std::uint8_t node;
  const Commands::Later& later;

  std::uint16_t index() const { return request.data.size() >= 3 ? le16(request.data, 0) : 0; }
  std::uint8_t sub() const { return request.data.size() >= 3 ? request.data[2] : 0; }
};

Outcome respond(Frame f, od::AbortCode code = od::AbortCode::none) {
  Outcome o;
  o.response = std::move(f);
  o.code = code;
  return o;
}

Outcome error(const Call& c, od::AbortCode code) {
  return respond(sdo_error_response(c.node, c.index(), c.sub(), od::to_u32(code)), code);
}

std::span<const std::byte> as_bytes(std::span<const std::uint8_t> d) { return std::as_bytes(d); }

// A dictionary write of `value`; `answer` turns the dictionary's result into the response frame.
template <class Answer>
Outcome write(const Call& c, std::uint16_t index, std::uint8_t sub, std::span<const std::uint8_t> value,
              Answer answer) {
  od::Done done;
  if (c.later) {
    done = [later = c.later, answer](od::AbortCode code) {
      // A completion that is still `pending` or none of the §4 codes is a hook's bug: general error.
      later(answer(code == od::AbortCode::pending ? od::AbortCode::general : code), code);
    };
  }
  const od::AbortCode code =
      c.od.write_bytes(index, sub, as_bytes(value), od::SdoLength::indicated, od::Origin::sdo, std::move(done));
  if (code == od::AbortCode::pending) {
    Outcome o;
    o.kind = Outcome::Kind::pending;
    o.code = code;
    return o;
  }
  return respond(answer(code), code);
}

Outcome reset_node(const Call&) {
  // Data bytes are ignored: the AN191 library sends L = 6 with two undefined bytes (§5).
  Outcome o;
  o.kind = Outcome::Kind::none;
  o.reset_node = true;
  return o;
}

Outcome sdo_read(const Call& c) {
  if (c.request.data.size() != 3) return error(c, od::AbortCode::unknown_command);
  const auto r = c.od.read_bytes(c.index(), c.sub());
  if (!r) return error(c, r.error());
  const auto bytes = std::span<const std::byte>(*r).first(std::min(r->size(), k_max_value));
  const std::span<const std::uint8_t> value(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  return respond(sdo_read_response(c.node, c.index(), c.sub(), value));
}

Outcome sdo_write(const Call& c) {
  if (c.request.data.size() < 3) return error(c, od::AbortCode::unknown_command);
  const std::uint8_t node = c.node;
  const std::uint16_t index = c.index();
  const std::uint8_t sub = c.sub();
  return write(c, index, sub, c.request.data.subspan(3), [node, index, sub](od::AbortCode code) {
    return code == od::AbortCode::none ? sdo_write_response(node, index, sub)
                                       : sdo_error_response(node, index, sub, od::to_u32(code));
  });
}

Outcome sdo_abort(const Call& c) {
  // Nothing to cancel: every transfer is a single request/response (no block transfers).
  if (c.request.data.size() != 7) return error(c, od::AbortCode::unknown_command);
  return respond(abort_acknowledge(c.node, c.index(), c.sub()));
}

Outcome controlword(const Call& c) {
  const std::uint8_t node = c.node;
  return write(c, k_controlword, 0, c.request.data,
               [node](od::AbortCode code) { return controlword_response(node, code == od::AbortCode::none ? 0 : 1); });
}

Outcome unsupported(const Call& c) { return error(c, od::AbortCode::unknown_command); }

using Handler = Outcome (*)(const Call&);

struct Row {
  std::uint8_t code;
  const char* name;
  Handler handler;
};

// The command table (§5). Codes not listed answer 0x05040001.
constexpr std::array<Row, 5> k_rows = {{
    {command::reset_node, "reset node", reset_node},
    {command::sdo_read, "SDO read", sdo_read},
    {command::sdo_write, "SDO write", sdo_write},
    {command::sdo_abort, "abort request", sdo_abort},
    {command::controlword, "controlword", controlword},
}};

constexpr std::array<const Row*, 256> make_lookup() {
  std::array<const Row*, 256> t{};
  for (const auto& r : k_rows) t[r.code] = &r;
  return t;
}

constexpr auto k_lookup = make_lookup();

}  // namespace

Outcome Commands::handle(const FrameView& request, std::uint8_t node_id, const Later& later) const {
  const Call c{od_, request, node_id, later};
  const Row* row = k_lookup[request.command];
  return row ? row->handler(c) : unsupported(c);
}

const char* Commands::name(std::uint8_t code) {
  const Row* row = k_lookup[code];
  return row ? row->name : "unsupported";
}

}  // namespace mcemu::faulhaber
