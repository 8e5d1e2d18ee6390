// Fuzz target: the message codec between mcemu's loop and a script engine process
// (scripting/core/ipc, scripting.md §10.2). Since the sandbox (docs/security.md) a script that
// reaches the runner's internals can write any bytes on its socketpair: they are outside bytes.
//
// Input: the first byte is a step that cuts the rest into feed pieces; the rest is the stream the
// loop reads. Oracles: the frames decoded do not depend on how the stream arrived (every split of
// the same bytes gives the same messages and the same error); each message body that decodes as
// values, a call or a socket request encodes back to bytes that decode to the same thing.
#include <cstdint>
#include <string>
#include <vector>

#include "scripting/core/ipc.hpp"

namespace {

using namespace mcemu::scripting;

struct Result {
  std::vector<ipc::Message> messages;
  bool error = false;
};

// What the loop's pump does: append what arrived, take every complete frame, stop on an error.
Result drain(std::string_view stream, std::size_t piece) {
  Result r;
  std::string buffer;
  for (std::size_t at = 0; at < stream.size() && !r.error; at += piece) {
    buffer.append(stream.substr(at, piece));
    for (;;) {
      const auto d = ipc::decode(buffer);
      if (d.error) {
        r.error = true;
        break;
      }
      if (!d.message) break;
      if (d.consumed == 0 || d.consumed > buffer.size()) __builtin_trap();
      buffer.erase(0, d.consumed);
      r.messages.push_back(*d.message);
    }
  }
  return r;
}

bool same(const Result& a, const Result& b) {
  if (a.error != b.error || a.messages.size() != b.messages.size()) return false;
  for (std::size_t i = 0; i < a.messages.size(); ++i) {
    if (a.messages[i].kind != b.messages[i].kind || a.messages[i].body != b.messages[i].body) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::size_t step = 1 + data[0] % 64;
  const std::string_view stream(reinterpret_cast<const char*>(data + 1), size - 1);
  const Result whole = drain(stream, stream.size() + 1);
  if (!same(whole, drain(stream, step)) || !same(whole, drain(stream, 1))) __builtin_trap();
  for (const auto& m : whole.messages) {
    if (ipc::decode(ipc::encode(m.kind, m.body)).message->body != m.body) __builtin_trap();
    if (const auto v = ipc::decode_values(m.body)) {
      if (ipc::decode_values(ipc::encode_values(*v)) != v) __builtin_trap();
    }
    if (const auto c = ipc::decode_call(m.body)) {
      const auto back = ipc::decode_call(ipc::encode_call(*c));
      if (!back || back->function != c->function || back->args != c->args) __builtin_trap();
    }
    if (const auto n = ipc::decode_net(m.body)) {
      if (ipc::decode_net(ipc::encode_net(*n)) != n) __builtin_trap();
    }
  }
  return 0;
}
