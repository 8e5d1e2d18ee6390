// Block upload and block download of the SDO server (slcan-canopen.md §6.4–§6.6).
#include <algorithm>

#include "protocols/canopen/crc16.hpp"
#include "protocols/canopen/sdo_frames.hpp"
#include "protocols/canopen/sdo_server.hpp"

namespace mcemu::canopen {
namespace {

using sdo_frames::header;
using sdo_frames::put_u32;

}  // namespace

// ---- block upload (§6.5) -----------------------------------------------------------------------

void SdoServer::block_upload_initiate(const Payload& req, std::uint16_t index, std::uint8_t sub, Millis now,
                                      std::vector<Payload>& out) {
  if (auto c = od_.check_upload(index, sub); c != od::AbortCode::none) return abort(c, out);
  const int blksize = req[4];
  if (blksize == 0 || blksize > 127) return abort(od::AbortCode::invalid_block_size, out);
  auto bytes = od_.read_bytes(index, sub);
  if (!bytes) return abort(bytes.error(), out);
  const std::size_t pst = req[5];
  if (pst != 0 && bytes->size() <= pst) {
    upload_initiate(index, sub, now, out);  // protocol switch to an ordinary upload (CON)
    return;
  }
  BlockUpload s;
  s.crc = (req[0] & 0x04) != 0;
  s.blksize = blksize;
  s.data.resize(bytes->size());
  std::transform(bytes->begin(), bytes->end(), s.data.begin(),
                 [](std::byte b) { return std::to_integer<std::uint8_t>(b); });
  Payload p = header(s.crc ? 0xC6 : 0xC2, index, sub);
  put_u32(p, 4, static_cast<std::uint32_t>(s.data.size()));
  out.push_back(p);
  state_ = std::move(s);
  keep_alive(now);
}

void SdoServer::send_sub_block(BlockUpload& s, std::vector<Payload>& out) {
  s.sent = 0;
  s.sent_last = false;
  std::size_t pos = s.offset;
  while (s.sent < s.blksize && !s.sent_last) {
    const std::size_t chunk = std::min<std::size_t>(7, s.data.size() - pos);
    s.sent_last = pos + chunk == s.data.size();
    ++s.sent;
    Payload p{};
    p[0] = static_cast<std::uint8_t>((s.sent_last ? 0x80 : 0x00) | s.sent);
    std::copy_n(s.data.begin() + static_cast<std::ptrdiff_t>(pos), chunk, p.begin() + 1);
    out.push_back(p);
    pos += chunk;
  }
  s.phase = BlockUpload::Phase::ack;
}

void SdoServer::block_upload_request(const Payload& req, BlockUpload& s, Millis now, std::vector<Payload>& out) {
  const int ss = req[0] & 0x03;
  if (s.phase == BlockUpload::Phase::start && ss == 3) {
    if (injected_abort(SdoFaultPhase::segment, out)) return;
    send_sub_block(s, out);
    keep_alive(now);
    return;
  }
  if (s.phase == BlockUpload::Phase::ack && ss == 2) {
    const int ack = req[1];
    const int blk = req[2];
    if (blk == 0 || blk > 127) return abort(od::AbortCode::invalid_block_size, out);
    if (ack > s.sent) return abort(od::AbortCode::invalid_sequence, out);
    s.offset = std::min(s.data.size(), s.offset + 7 * static_cast<std::size_t>(ack));
    s.blksize = blk;
    if (ack == s.sent && s.sent_last) {
      if (injected_abort(SdoFaultPhase::end, out)) return;
      const std::size_t n = s.data.empty() ? 7 : (7 - s.data.size() % 7) % 7;
      Payload p{};
      p[0] = static_cast<std::uint8_t>(0xC1 | (n << 2));
      if (s.crc) {
        const std::uint16_t crc = crc16_ccitt(s.data);
        p[1] = static_cast<std::uint8_t>(crc & 0xFF);
        p[2] = static_cast<std::uint8_t>(crc >> 8);
      }
      out.push_back(p);
      s.phase = BlockUpload::Phase::end;
    } else {
      if (injected_abort(SdoFaultPhase::segment, out)) return;
      send_sub_block(s, out);  // the next sub-block, or a resend from the first unacknowledged byte
    }
    keep_alive(now);
    return;
  }
  if (s.phase == BlockUpload::Phase::end && ss == 1) {
    reset();  // end response: idle, no frame
    return;
  }
  abort(od::AbortCode::unknown_command, out);
}

// ---- block download (§6.4) ---------------------------------------------------------------------

void SdoServer::block_download_initiate(const Payload& req, std::uint16_t index, std::uint8_t sub, Millis now,
                                        std::vector<Payload>& out) {
  BlockDownload s;
  s.crc = (req[0] & 0x04) != 0;
  if ((req[0] & 0x02) != 0) {
    s.size =
        static_cast<std::size_t>(req[4] | (req[5] << 8) | (req[6] << 16)) | (static_cast<std::size_t>(req[7]) << 24);
  }
  if (auto c = od_.check_download(index, sub, s.size); c != od::AbortCode::none) return abort(c, out);
  s.blksize = std::clamp(config_.sdo_block_size, 1, 127);
  Payload p = header(s.crc ? 0xA4 : 0xA0, index, sub);
  p[4] = static_cast<std::uint8_t>(s.blksize);
  out.push_back(p);
  state_ = std::move(s);
  keep_alive(now);
}

void SdoServer::block_download_segment(const Payload& req, BlockDownload& s, Millis now, std::vector<Payload>& out) {
  const int seq = req[0] & 0x7F;
  const bool last = (req[0] & 0x80) != 0;
  if (seq == 0 || seq > s.blksize) return abort(od::AbortCode::invalid_sequence, out);
  keep_alive(now);
  const auto ack = [&](int acked) {
    Payload p{};
    p[0] = 0xA2;
    p[1] = static_cast<std::uint8_t>(acked);
    p[2] = static_cast<std::uint8_t>(s.blksize);
    out.push_back(p);
    s.last_seq = 0;
    s.skipping = false;
  };
  if (s.skipping || seq != s.last_seq + 1) {
    // Out of order or a duplicate: ignored with the rest of this sub-block; the client resends
    // from ack + 1 after the A2 that ends the sub-block (CiA 301).
    s.skipping = true;
    if (seq == s.blksize || last) ack(s.last_seq);
    return;
  }
  ++s.segments;
  const auto limit = s.size ? s.size : max_size();
  if (limit && s.segments > 1 && 7 * (s.segments - 1) >= *limit) return abort(od::AbortCode::length_too_high, out);
  if (s.data.size() + 7 > k_max_transfer) return abort(od::AbortCode::out_of_memory, out);
  s.data.insert(s.data.end(), req.begin() + 1, req.end());
  s.last_seq = seq;
  if ((last || seq == s.blksize) && injected_abort(SdoFaultPhase::segment, out)) return;
  if (last) {
    ack(seq);
    s.awaiting_end = true;
  } else if (seq == s.blksize) {
    ack(seq);
  }
}

void SdoServer::block_download_end(const Payload& req, BlockDownload& s, std::vector<Payload>& out) {
  if (injected_abort(SdoFaultPhase::end, out)) return;
  const std::size_t n = (req[0] >> 2) & 0x07;
  const std::size_t total = s.data.size() >= n ? s.data.size() - n : 0;
  s.data.resize(total);
  if (s.size && total > *s.size) return abort(od::AbortCode::length_too_high, out);
  if (s.size && total < *s.size) return abort(od::AbortCode::length_too_low, out);
  if (const auto max = max_size(); !s.size && max && total != *max) return abort(od::AbortCode::type_mismatch, out);
  if (s.crc) {
    const auto crc = static_cast<std::uint16_t>(req[1] | (req[2] << 8));
    if (crc16_ccitt(s.data) != crc) return abort(od::AbortCode::crc_error, out);
  }
  Payload done{};
  done[0] = 0xA1;
  const auto data = std::move(s.data);
  const bool indicated = s.size.has_value();
  finish_download(data, indicated ? od::SdoLength::indicated : od::SdoLength::segmented_unindicated, done, out);
}

}  // namespace mcemu::canopen
