// Dispatch, expedited and segmented transfers, pending completions and the timeout of the SDO
// server. Block transfers are in sdo_block.cpp.
#include "protocols/canopen/sdo_server.hpp"

#include <algorithm>
#include <utility>

#include "protocols/canopen/sdo_frames.hpp"

namespace mcemu::canopen {

struct SdoServer::Shared {
  struct Completion {
    std::uint64_t serial;
    od::AbortCode code;
  };
  std::vector<Completion> completions;
  std::function<void()> wake;
};

namespace {

using sdo_frames::get_u32;
using sdo_frames::header;
using sdo_frames::put_u32;

std::span<const std::byte> as_bytes(std::span<const std::uint8_t> d) {
  return {reinterpret_cast<const std::byte*>(d.data()), d.size()};
}

}  // namespace

Payload sdo_abort_payload(std::uint16_t index, std::uint8_t sub, od::AbortCode code) {
  Payload p = header(0x80, index, sub);
  put_u32(p, 4, od::to_u32(code));
  return p;
}

SdoServer::SdoServer(od::ObjectDictionary& od, const CanopenConfig& config, std::function<void()> after_write)
    : od_(od), config_(config), after_write_(std::move(after_write)), shared_(std::make_shared<Shared>()) {}

SdoServer::~SdoServer() = default;

void SdoServer::set_wake(std::function<void()> wake) { shared_->wake = std::move(wake); }

bool SdoServer::idle() const { return std::holds_alternative<Idle>(state_); }

bool SdoServer::has_completions() const { return !shared_->completions.empty(); }

void SdoServer::reset() {
  state_ = Idle{};
  deadline_.reset();
}

std::optional<Millis> SdoServer::next_deadline() const {
  if (idle() || std::holds_alternative<Pending>(state_)) return std::nullopt;
  return deadline_;
}

void SdoServer::abort(od::AbortCode code, std::vector<Payload>& out) {
  out.push_back(sdo_abort_payload(index_, sub_, code));
  reset();
}

std::optional<std::size_t> SdoServer::max_size() const {
  const od::EntryInfo* info = od_.info(index_, sub_);
  if (info == nullptr || od::is_string(info->type)) return std::nullopt;
  return od::size_of(info->type);
}

void SdoServer::on_request(const Payload& req, Millis now, std::vector<Payload>& out) {
  collect(now, out);
  const std::size_t before = out.size();
  const auto* pending_before = std::get_if<Pending>(&state_);
  const std::uint64_t serial_before = pending_before ? pending_before->serial : 0;
  handle(req, now, out);
  auto* pending = std::get_if<Pending>(&state_);
  const bool now_pending = pending != nullptr && pending->serial != serial_before;
  if ((out.size() == before && !now_pending) || !faults_.no_reply || !faults_.no_reply(index_)) return;
  out.resize(before);
  if (now_pending) pending->silent = true;
}

bool SdoServer::injected_abort(SdoFaultPhase phase, std::vector<Payload>& out) {
  if (!faults_.abort) return false;
  const auto code = faults_.abort(index_, sub_, phase);
  if (!code) return false;
  abort(static_cast<od::AbortCode>(*code), out);
  return true;
}

void SdoServer::handle(const Payload& req, Millis now, std::vector<Payload>& out) {
  const std::uint8_t b0 = req[0];
  const int ccs = b0 >> 5;
  const auto req_index = static_cast<std::uint16_t>(req[1] | (req[2] << 8));
  const std::uint8_t req_sub = req[3];

  // Inside a block-download sub-block every byte 0 is a sequence number, except 0x80 (§6.4).
  if (auto* bd = std::get_if<BlockDownload>(&state_); bd != nullptr && !bd->awaiting_end) {
    if (b0 == 0x80) {
      reset();
      return;
    }
    block_download_segment(req, *bd, now, out);
    return;
  }
  if (ccs == 4) {  // client abort, whatever it carries; cancels a pending response too
    reset();
    return;
  }
  if (ccs == 7) {
    if (idle()) {
      index_ = req_index;
      sub_ = req_sub;
    }
    abort(od::AbortCode::unknown_command, out);
    return;
  }
  const bool initiate = ccs == 1 || ccs == 2 || (ccs == 5 && (b0 & 0x03) == 0) || (ccs == 6 && (b0 & 0x01) == 0);
  if (initiate) {
    reset();  // an old transfer is dropped silently (§6.7)
    index_ = req_index;
    sub_ = req_sub;
    if (injected_abort(SdoFaultPhase::initiate, out)) return;
    switch (ccs) {
      case 1: download_initiate(req, req_index, req_sub, now, out); return;
      case 2: upload_initiate(req_index, req_sub, now, out); return;
      case 5: block_upload_initiate(req, req_index, req_sub, now, out); return;
      default: block_download_initiate(req, req_index, req_sub, now, out); return;
    }
  }
  if (idle()) {
    // Segments carry no index: the abort names 0000h.00; block sub-commands name bytes 1…3.
    const bool segment = ccs == 0 || ccs == 3;
    index_ = segment ? 0 : req_index;
    sub_ = segment ? 0 : req_sub;
    abort(od::AbortCode::unknown_command, out);
    return;
  }
  if (auto* su = std::get_if<SegUpload>(&state_); su != nullptr && ccs == 3) {
    upload_segment(req, *su, now, out);
    return;
  }
  if (auto* sd = std::get_if<SegDownload>(&state_); sd != nullptr && ccs == 0) {
    download_segment(req, *sd, now, out);
    return;
  }
  if (auto* bd = std::get_if<BlockDownload>(&state_); bd != nullptr && ccs == 6 && (b0 & 0x01) != 0) {
    block_download_end(req, *bd, out);
    return;
  }
  if (auto* bu = std::get_if<BlockUpload>(&state_); bu != nullptr && ccs == 5) {
    block_upload_request(req, *bu, now, out);
    return;
  }
  abort(od::AbortCode::unknown_command, out);  // wrong kind of request for the state (§6.7)
}

void SdoServer::collect(Millis, std::vector<Payload>& out) {
  auto completions = std::exchange(shared_->completions, {});
  for (const auto& c : completions) {
    auto* p = std::get_if<Pending>(&state_);
    if (p == nullptr || p->serial != c.serial) continue;  // cancelled
    if (p->silent) {
      reset();
    } else if (c.code == od::AbortCode::none) {
      out.push_back(p->success);
      reset();
    } else {
      abort(c.code == od::AbortCode::pending ? od::AbortCode::general : c.code, out);
    }
  }
}

void SdoServer::advance(Millis now, std::vector<Payload>& out) {
  collect(now, out);
  if (const auto d = next_deadline(); d && now >= *d) abort(od::AbortCode::sdo_timeout, out);
}

// ---- expedited and segmented upload (§6.2, §6.3) ----------------------------------------------

void SdoServer::upload_initiate(std::uint16_t index, std::uint8_t sub, Millis now, std::vector<Payload>& out) {
  if (auto c = od_.check_upload(index, sub); c != od::AbortCode::none) return abort(c, out);
  auto bytes = od_.read_bytes(index, sub);
  if (!bytes) return abort(bytes.error(), out);
  std::vector<std::uint8_t> data(bytes->size());
  std::transform(bytes->begin(), bytes->end(), data.begin(),
                 [](std::byte b) { return std::to_integer<std::uint8_t>(b); });
  if (!data.empty() && data.size() <= 4) {
    if (injected_abort(SdoFaultPhase::end, out)) return;  // the one exchange ends the transfer
    Payload p = header(static_cast<std::uint8_t>(0x43 | ((4 - data.size()) << 2)), index, sub);
    std::copy(data.begin(), data.end(), p.begin() + 4);
    out.push_back(p);
    return;
  }
  Payload p = header(0x41, index, sub);
  put_u32(p, 4, static_cast<std::uint32_t>(data.size()));
  out.push_back(p);
  state_ = SegUpload{std::move(data), 0, 0};
  keep_alive(now);
}

void SdoServer::upload_segment(const Payload& req, SegUpload& s, Millis now, std::vector<Payload>& out) {
  const int t = (req[0] >> 4) & 1;
  if (t != s.toggle) return abort(od::AbortCode::toggle_bit, out);
  const std::size_t chunk = std::min<std::size_t>(7, s.data.size() - s.pos);
  const bool last = s.pos + chunk == s.data.size();
  if (injected_abort(SdoFaultPhase::segment, out) || (last && injected_abort(SdoFaultPhase::end, out))) return;
  Payload p{};
  p[0] = static_cast<std::uint8_t>((t << 4) | ((7 - chunk) << 1) | (last ? 1 : 0));
  std::copy_n(s.data.begin() + static_cast<std::ptrdiff_t>(s.pos), chunk, p.begin() + 1);
  out.push_back(p);
  if (last) {
    reset();
    return;
  }
  s.pos += chunk;
  s.toggle ^= 1;
  keep_alive(now);
}

// ---- expedited and segmented download (§6.2, §6.3) --------------------------------------------

void SdoServer::download_initiate(const Payload& req, std::uint16_t index, std::uint8_t sub, Millis now,
                                  std::vector<Payload>& out) {
  const bool expedited = (req[0] & 0x02) != 0;
  const bool size_indicated = (req[0] & 0x01) != 0;
  const Payload success = header(0x60, index, sub);
  if (expedited) {
    if (injected_abort(SdoFaultPhase::end, out)) return;  // the one exchange ends the transfer
    const std::size_t n = size_indicated ? 4 - ((req[0] >> 2) & 0x03) : 4;
    finish_download(std::span<const std::uint8_t>(req.data() + 4, n),
                    size_indicated ? od::SdoLength::indicated : od::SdoLength::expedited_unindicated, success, out);
    return;
  }
  std::optional<std::size_t> size;
  if (size_indicated) size = get_u32(req, 4);
  if (auto c = od_.check_download(index, sub, size); c != od::AbortCode::none) return abort(c, out);
  out.push_back(success);
  state_ = SegDownload{size, {}, 0};
  keep_alive(now);
}

void SdoServer::download_segment(const Payload& req, SegDownload& s, Millis now, std::vector<Payload>& out) {
  const int t = (req[0] >> 4) & 1;
  if (t != s.toggle) return abort(od::AbortCode::toggle_bit, out);
  const std::size_t n = (req[0] >> 1) & 0x07;
  const bool last = (req[0] & 0x01) != 0;
  if (injected_abort(SdoFaultPhase::segment, out) || (last && injected_abort(SdoFaultPhase::end, out))) return;
  s.data.insert(s.data.end(), req.begin() + 1, req.begin() + 1 + static_cast<std::ptrdiff_t>(7 - n));
  const auto limit = s.size ? s.size : max_size();
  if (limit && s.data.size() > *limit) return abort(od::AbortCode::length_too_high, out);
  if (s.data.size() > k_max_transfer) return abort(od::AbortCode::out_of_memory, out);
  Payload ok{};
  ok[0] = static_cast<std::uint8_t>(0x20 | (t << 4));
  if (!last) {
    out.push_back(ok);
    s.toggle ^= 1;
    keep_alive(now);
    return;
  }
  if (s.size && s.data.size() < *s.size) return abort(od::AbortCode::length_too_low, out);
  const auto data = std::move(s.data);
  finish_download(data, s.size ? od::SdoLength::indicated : od::SdoLength::segmented_unindicated, ok, out);
}

void SdoServer::finish_download(std::span<const std::uint8_t> data, od::SdoLength length, const Payload& success,
                                std::vector<Payload>& out) {
  const std::uint64_t serial = next_serial_++;
  std::weak_ptr<Shared> weak = shared_;
  od::Done done = [weak, serial](od::AbortCode code) {
    if (auto s = weak.lock()) {
      s->completions.push_back({serial, code});
      if (s->wake) s->wake();
    }
  };
  const od::AbortCode code = od_.write_bytes(index_, sub_, as_bytes(data), length, od::Origin::sdo, std::move(done));
  if (after_write_) after_write_();
  if (code == od::AbortCode::pending) {
    state_ = Pending{serial, success};
    deadline_.reset();
    collect(Millis{0}, out);  // the completion may already have arrived inside the write
    return;
  }
  if (code != od::AbortCode::none) return abort(code, out);
  out.push_back(success);
  reset();
}

}  // namespace mcemu::canopen
