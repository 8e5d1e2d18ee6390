#include "protocols/slcan/session.hpp"

#include <utility>

namespace mcemu::slcan {

namespace {

std::string_view state_name(ChannelState s) {
  switch (s) {
    case ChannelState::open: return "OPEN";
    case ChannelState::listen: return "LISTEN";
    case ChannelState::closed: return "CLOSED";
  }
  return "?";
}

}  // namespace

Session::Session(SlcanConfig config, ToNode to_node, SerialSource serial)
    : config_(std::move(config)), to_node_(std::move(to_node)), serial_(std::move(serial)) {}

void Session::receive(std::string_view bytes) {
  if (finished()) return;
  std::vector<line::Line> lines;
  assembler_.feed(bytes, lines);
  for (const auto& l : lines) handle_line(l);
}

std::string Session::take_output() { return std::exchange(output_, {}); }

void Session::peer_closed() {
  // Every complete line has been answered inside receive(); the unterminated rest is dropped.
  assembler_.reset();
  peer_closed_ = true;
}

void Session::handle_line(const line::Line& l) {
  if (trace_) trace_({TraceEvent::Dir::rx, l.overlong ? l.raw.substr(0, k_max_line) : l.raw, l.overlong});
  if (l.overlong) {
    event(std::string("BEL: ") + std::string(to_string(ParseError::overlong)));
    reply("\a");
    return;
  }
  if (bel_ && bel_()) {
    event("BEL: injected (slcan.bel)");
    reply("\a");
    return;
  }
  const ParseResult r = parse_line(l.text);
  if (const auto* e = std::get_if<ParseError>(&r)) {
    event(std::string("BEL: ") + std::string(to_string(*e)));
    reply("\a");
    return;
  }
  apply(std::get<Command>(r));
}

void Session::apply(const Command& c) {
  switch (c.kind) {
    case CommandKind::empty: reply("\r"); return;
    case CommandKind::open:
      set_state(ChannelState::open);
      reply("\r");
      return;
    case CommandKind::listen:
      set_state(ChannelState::listen);
      reply("\r");
      return;
    case CommandKind::close:
      set_state(ChannelState::closed);
      reply("\r");
      return;
    case CommandKind::bitrate:
      bitrate_code_ = static_cast<int>(c.arg);
      reply("\r");
      return;
    case CommandKind::btr:
      btr_ = c.arg;
      reply("\r");
      return;
    case CommandKind::acceptance_code:
      acceptance_code_ = c.arg;
      reply("\r");
      return;
    case CommandKind::acceptance_mask:
      acceptance_mask_ = c.arg;
      reply("\r");
      return;
    case CommandKind::setting: reply("\r"); return;
    case CommandKind::timestamps:
      timestamps_ = c.arg == 1;
      reply("\r");
      return;
    case CommandKind::version: reply("V" + config_.version + "\r"); return;
    case CommandKind::version_lower: reply("v" + config_.version + "\r"); return;
    case CommandKind::flags: reply("F00\r"); return;
    case CommandKind::serial: {
      static constexpr char k_hex[] = "0123456789ABCDEF";
      const std::uint32_t serial = serial_ ? serial_() : 0;
      std::string text = "N";
      for (int i = config_.serial_digits - 1; i >= 0; --i) text.push_back(k_hex[(serial >> (4 * i)) & 0xF]);
      reply(text + "\r");
      return;
    }
    case CommandKind::frame: {
      if (state_ != ChannelState::open) {
        event("BEL: frame while " + std::string(state_name(state_)));
        reply("\a");
        return;
      }
      if (config_.frame_ack == FrameAck::z) {
        reply(c.frame.extended ? "Z\r" : "z\r");
      } else if (config_.frame_ack == FrameAck::cr) {
        reply("\r");
      }
      if (to_node_) to_node_(c.frame);
      return;
    }
  }
}

void Session::reply(std::string_view text) { queue(text, false); }

void Session::deliver(const can::Frame& frame, std::chrono::milliseconds stamp) {
  if (state_ == ChannelState::closed || finished()) return;
  const std::string line = encode_frame(frame, timestamps_ ? std::optional(stamp) : std::nullopt);
  queue(line, true);
}

void Session::send_raw(std::string_view text) {
  if (finished() || text.empty()) return;
  queue(text, true);
}

void Session::queue(std::string_view text, bool from_node) {
  output_.append(text);
  if (trace_) trace_({TraceEvent::Dir::tx, std::string(text), false});
  // Replies are collected by the adapter after receive(); node frames may arrive at any time.
  if (from_node) wake();
}

void Session::event(std::string text) {
  if (trace_) trace_({TraceEvent::Dir::event, std::move(text), false});
}

void Session::set_state(ChannelState s) {
  if (s != state_) event(std::string("state ") + std::string(state_name(s)));
  state_ = s;
}

}  // namespace mcemu::slcan
