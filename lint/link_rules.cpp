#include "lint/link_rules.hpp"

#include <string>

namespace mcemu::lint {

namespace {

struct LinkRuleIds {
  RuleId before_reply;
  RuleId faster;
};

LinkRuleIds ids(Link l) {
  if (l == Link::refgo) return {RuleId::refgo_request_before_reply, RuleId::refgo_faster_than_drive};
  return {RuleId::faulhaber_request_before_reply, RuleId::faulhaber_faster_than_drive};
}

}  // namespace

std::string_view to_string(Link l) { return l == Link::refgo ? "refgo" : "faulhaber"; }

LinkRules::Slot* LinkRules::find(Conn conn) {
  for (auto& s : slots_) {
    if (s.used && s.conn == conn) return &s;
  }
  return nullptr;
}

LinkRules::Slot& LinkRules::slot(Conn conn, Link link) {
  Slot* s = find(conn);
  if (!s) {
    s = &slots_[0];
    for (auto& c : slots_) {
      if (!c.used) {
        s = &c;
        break;
      }
      if (c.lru < s->lru) s = &c;
    }
    *s = Slot{};
    s->used = true;
    s->conn = conn;
    s->link = link;
  }
  s->lru = ++tick_;
  return *s;
}

void LinkRules::on_request(const ProtocolRequest& r, const At& at, Reporter& rep) {
  Slot& s = slot(r.conn, r.link);
  const LinkRuleIds rule = ids(r.link);
  if (s.unanswered > 0 && at.mono - s.unanswered_since >= k_forget_ms) s.unanswered = 0;

  const bool same_read = r.chunk != 0 && r.chunk == s.reply_chunk;
  const bool before_reply = s.unanswered > 0 || same_read;
  if (before_reply) {
    rep.fire(rule.before_reply, at, [&] {
      return std::string(s.unanswered > 0 ? "request while " + std::to_string(s.unanswered) + " repl" +
                                                (s.unanswered == 1 ? "y is" : "ies are") + " outstanding"
                                          : std::string("request in the same read as the previous one")) +
             " on this connection";
    });
  } else if (s.has_request) {
    // The weaker finding only when the stronger one did not fire for this request.
    const std::uint32_t min_ms =
        r.link == Link::refgo ? config_->refgo_min_response_ms : config_->faulhaber_min_response_ms;
    const Ms gap = at.mono - s.last_request;
    if (min_ms > 0 && gap < min_ms) {
      rep.fire(rule.faster, at, [&] {
        return "request " + std::to_string(gap) + " ms after the previous one (real drive model: ≥ " +
               std::to_string(min_ms) + " ms per reply)";
      });
    }
  }

  if (r.link == Link::faulhaber) {
    if (s.cw_notified && r.chunk != 0 && r.chunk == s.cw_chunk) {
      rep.fire(RuleId::faulhaber_request_before_notification, at, [] {
        return std::string("request in the same read as a controlword write, before its statusword notification");
      });
    } else if (s.cw_waiting && !s.suspect) {
      s.suspect = at;  // reported when the notification comes (it may never: notifications off)
    }
    if (r.chunk != s.cw_chunk) s.cw_notified = false;
    if (r.expects_reply) answering_ = r.conn;
  }

  s.has_request = true;
  s.last_request = at.mono;
  if (r.expects_reply) {
    if (s.unanswered == 0) s.unanswered_since = at.mono;
    ++s.unanswered;
    s.reply_chunk = r.chunk;
  }
}

void LinkRules::on_reply(const ProtocolReply& r, const At&, Reporter& rep) {
  if (r.kind == ReplyKind::notification) {
    for (auto& s : slots_) {
      if (!s.used || s.link != Link::faulhaber || !s.cw_waiting) continue;
      s.cw_waiting = false;
      s.cw_notified = true;
      if (s.suspect) {
        const At a = *s.suspect;
        s.suspect.reset();
        rep.fire(RuleId::faulhaber_request_before_notification, a,
                 [] { return std::string("request after a controlword write, before its statusword notification"); });
      }
    }
    return;
  }
  Slot* s = find(r.conn);
  if (!s) return;
  if (s->unanswered > 0) --s->unanswered;
  if (r.conn == answering_) answering_ = 0;
}

void LinkRules::on_statusword_change_by(Conn conn) {
  Slot* s = find(conn != 0 ? conn : answering_);
  if (!s || s->link != Link::faulhaber) return;
  s->cw_waiting = true;
  s->cw_chunk = s->reply_chunk;
  s->cw_notified = false;
  s->suspect.reset();
}

void LinkRules::on_closed(Conn conn) {
  if (Slot* s = find(conn)) *s = Slot{};
  if (answering_ == conn) answering_ = 0;
}

void LinkRules::power_on() {
  for (auto& s : slots_) {
    s.cw_waiting = false;
    s.cw_notified = false;
    s.suspect.reset();
  }
}

}  // namespace mcemu::lint
