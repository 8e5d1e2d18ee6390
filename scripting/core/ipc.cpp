#include "scripting/core/ipc.hpp"

namespace mcemu::scripting::ipc {

namespace {

std::uint64_t get_le(std::string_view s, std::size_t at, std::size_t n) {
  std::uint64_t v = 0;
  for (std::size_t k = 0; k < n; ++k) v |= static_cast<std::uint64_t>(static_cast<unsigned char>(s[at + k])) << (8 * k);
  return v;
}

void put_le(std::string& out, std::uint64_t v, std::size_t n) {
  for (std::size_t k = 0; k < n; ++k) out += static_cast<char>((v >> (8 * k)) & 0xFF);
}

bool known_kind(char c) {
  switch (static_cast<Kind>(c)) {
    case Kind::hello:
    case Kind::compiled:
    case Kind::call:
    case Kind::output:
    case Kind::sleep:
    case Kind::cancel:
    case Kind::end:
    case Kind::fatal:
    case Kind::log:
    case Kind::net:
    case Kind::start:
    case Kind::reply:
    case Kind::wake: return true;
  }
  return false;
}

}  // namespace

Decoded decode(std::string_view buffer) {
  Decoded d;
  if (buffer.size() < k_header) return d;
  const std::uint64_t n = get_le(buffer, 0, k_header);
  if (n == 0 || n > k_max_payload) {
    d.error = true;
    return d;
  }
  if (buffer.size() < k_header + n) return d;
  if (!known_kind(buffer[k_header])) {
    d.error = true;
    return d;
  }
  d.consumed = k_header + static_cast<std::size_t>(n);
  d.message = Message{static_cast<Kind>(buffer[k_header]), std::string(buffer.substr(k_header + 1, n - 1))};
  return d;
}

std::string encode(Kind kind, std::string_view body) {
  std::string out;
  out.reserve(k_header + 1 + body.size());
  put_le(out, body.size() + 1, k_header);
  out += static_cast<char>(kind);
  out += body;
  return out;
}

std::string encode_values(std::span<const Value> values) {
  std::string out;
  put_le(out, values.size() & 0xFFFF, 2);
  for (const auto& v : values) {
    out += static_cast<char>(v.tag);
    switch (v.tag) {
      case Value::Tag::none: break;
      case Value::Tag::integer: put_le(out, static_cast<std::uint64_t>(v.i), 8); break;
      case Value::Tag::bytes:
      case Value::Tag::text:
        put_le(out, v.s.size(), 4);
        out += v.s;
        break;
    }
  }
  return out;
}

std::optional<std::vector<Value>> decode_values(std::string_view body) {
  if (body.size() < 2) return std::nullopt;
  const auto count = static_cast<std::size_t>(get_le(body, 0, 2));
  std::size_t at = 2;
  // Every value takes at least its tag byte: a count beyond the bytes left is refused before any
  // memory is reserved for it (two bytes must not make the loop reserve 65 535 values).
  if (count > body.size() - at) return std::nullopt;
  std::vector<Value> out;
  out.reserve(count);
  for (std::size_t k = 0; k < count; ++k) {
    if (at >= body.size()) return std::nullopt;
    const char tag = body[at++];
    switch (static_cast<Value::Tag>(tag)) {
      case Value::Tag::none: out.push_back(Value::none()); break;
      case Value::Tag::integer:
        if (body.size() - at < 8) return std::nullopt;
        out.push_back(Value::integer(static_cast<std::int64_t>(get_le(body, at, 8))));
        at += 8;
        break;
      case Value::Tag::bytes:
      case Value::Tag::text: {
        if (body.size() - at < 4) return std::nullopt;
        const std::uint64_t n = get_le(body, at, 4);
        at += 4;
        if (body.size() - at < n) return std::nullopt;
        std::string s(body.substr(at, static_cast<std::size_t>(n)));
        at += static_cast<std::size_t>(n);
        out.push_back(static_cast<Value::Tag>(tag) == Value::Tag::bytes ? Value::bytes(std::move(s))
                                                                        : Value::text(std::move(s)));
        break;
      }
      default: return std::nullopt;
    }
  }
  if (at != body.size()) return std::nullopt;
  return out;
}

std::string encode_call(const Call& call) {
  std::string out;
  put_le(out, call.function, 2);
  out += encode_values(call.args);
  return out;
}

std::optional<Call> decode_call(std::string_view body) {
  if (body.size() < 2) return std::nullopt;
  auto values = decode_values(body.substr(2));
  if (!values) return std::nullopt;
  return Call{static_cast<std::uint16_t>(get_le(body, 0, 2)), std::move(*values)};
}

namespace {

constexpr std::string_view k_net_kinds[] = {"server", "client", "udp"};

}  // namespace

std::string encode_net(const NetRequest& request) {
  const Value values[] = {Value::text(std::string(k_net_kinds[static_cast<std::size_t>(request.kind)])),
                          Value::text(request.host), Value::integer(request.port)};
  return encode_values(values);
}

std::optional<NetRequest> decode_net(std::string_view body) {
  const auto v = decode_values(body);
  if (!v || v->size() != 3 || (*v)[0].tag != Value::Tag::text || (*v)[1].tag != Value::Tag::text ||
      (*v)[2].tag != Value::Tag::integer || (*v)[2].i < 1 || (*v)[2].i > 65535) {
    return std::nullopt;
  }
  NetRequest r;
  std::size_t k = 0;
  while (k < std::size(k_net_kinds) && k_net_kinds[k] != (*v)[0].s) ++k;
  if (k == std::size(k_net_kinds)) return std::nullopt;
  r.kind = static_cast<NetRequest::Kind>(k);
  r.host = (*v)[1].s;
  r.port = static_cast<std::uint16_t>((*v)[2].i);
  if (r.kind == NetRequest::Kind::client && r.host.empty()) return std::nullopt;
  return r;
}

}  // namespace mcemu::scripting::ipc
