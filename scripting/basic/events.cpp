#include "scripting/basic/events.hpp"

#include <cstdio>

namespace mcemu::basic {

std::string_view to_string(EventKind k) {
  switch (k) {
    case EventKind::started: return "start";
    case EventKind::stopped: return "stop";
    case EventKind::finished: return "end";
    case EventKind::error: return "error";
    case EventKind::setobj: return "setobj";
    case EventKind::save: return "save";
  }
  return "?";
}

std::string describe(const Event& e) {
  std::string out(to_string(e.kind));
  char buf[64];
  switch (e.kind) {
    case EventKind::started:
    case EventKind::finished: out += " slot " + std::to_string(e.slot); break;
    case EventKind::stopped: out += " slot " + std::to_string(e.slot) + " (" + e.message + ")"; break;
    case EventKind::error:
      out += " slot " + std::to_string(e.slot) + " line " + std::to_string(e.line) + ": " + e.message;
      break;
    case EventKind::setobj:
      std::snprintf(buf, sizeof buf, " line %u %04Xh.%02X = %lld", e.line, e.index, e.sub,
                    static_cast<long long>(e.value));
      out += buf;
      if (e.code != od::AbortCode::none) {
        std::snprintf(buf, sizeof buf, " refused %08X", od::to_u32(e.code));
        out += buf;
      }
      break;
    case EventKind::save:
      out += " line " + std::to_string(e.line);
      for (const auto& v : e.saved) {
        out += ' ';
        out += static_cast<char>('a' + v.var);
        out += '=' + std::to_string(v.value);
      }
      out += " (#" + std::to_string(e.save_count) + ")";
      break;
  }
  return out;
}

}  // namespace mcemu::basic
