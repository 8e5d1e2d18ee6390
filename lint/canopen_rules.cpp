#include "lint/canopen_rules.hpp"

#include <cstdio>
#include <string>

namespace mcemu::lint {

namespace {

std::string_view kind_name(CanKind k) {
  switch (k) {
    case CanKind::nmt: return "NMT command";
    case CanKind::sync: return "SYNC";
    case CanKind::sdo: return "SDO request";
    case CanKind::guarding: return "guarding RTR";
    case CanKind::rpdo: return "RPDO";
    case CanKind::other: break;
  }
  return "frame";
}

// SDO client command specifier (bits 7…5 of byte 0, slcan-canopen.md §6.1).
constexpr std::uint8_t ccs(std::uint8_t byte0) { return static_cast<std::uint8_t>(byte0 >> 5); }

}  // namespace

std::string_view to_string(Nmt n) {
  switch (n) {
    case Nmt::initialising: return "INITIALISING";
    case Nmt::stopped: return "STOPPED";
    case Nmt::operational: return "OPERATIONAL";
    case Nmt::pre_operational: break;
  }
  return "PRE-OPERATIONAL";
}

void CanopenRules::on_nmt(const NmtChange& n) {
  nmt_ = n.to;
  guarding_reported_ = false;  // once per OPERATIONAL stretch
  if (n.to == Nmt::initialising) {
    // a reset ends every transfer silently and restarts guarding (slcan-canopen.md §4.4)
    sdo_waiting_ = false;
    block_download_ = false;
    guarding_seen_ = false;
  }
}

void CanopenRules::on_request(const CanRequest& r, const At& at, Reporter& rep) {
  if (nmt_ == Nmt::initialising && r.kind != CanKind::other && r.kind != CanKind::sync) {
    rep.fire(RuleId::canopen_traffic_before_bootup, at,
             [&] { return std::string(kind_name(r.kind)) + " while the node is INITIALISING (no boot-up yet)"; });
    return;
  }
  switch (r.kind) {
    case CanKind::sdo: {
      const std::uint8_t cs = ccs(r.byte0);
      if (cs == 4) {  // client abort: nothing is answered, the transfer is over
        sdo_waiting_ = false;
        block_download_ = false;
        return;
      }
      if (nmt_ == Nmt::stopped) {
        rep.fire(RuleId::canopen_sdo_while_stopped, at, [&] {
          char buf[64];
          std::snprintf(buf, sizeof buf, "SDO request (byte 0 = 0x%02X) to a STOPPED node", r.byte0);
          return std::string(buf);
        });
        sdo_waiting_ = false;  // no answer will come
        return;
      }
      if (block_download_) return;  // sub-block segments are answered per sub-block
      if (sdo_waiting_) {
        rep.fire(RuleId::canopen_sdo_overlap, at, [&] {
          char buf[80];
          std::snprintf(buf, sizeof buf, "SDO request (byte 0 = 0x%02X) before the answer to the previous one",
                        r.byte0);
          return std::string(buf);
        });
      }
      // A block upload's end response (ccs 5, ss 1) is the client's last word: no answer follows.
      sdo_waiting_ = !(cs == 5 && (r.byte0 & 0x03) == 1);
      if (cs == 6 && (r.byte0 & 0x01) == 0) block_download_ = true;
      return;
    }
    case CanKind::rpdo:
      if (nmt_ == Nmt::pre_operational || nmt_ == Nmt::stopped) {
        rep.fire(RuleId::canopen_rpdo_not_operational, at, [&] {
          return "RPDO" + std::to_string(r.rpdo) + " in " + std::string(to_string(*nmt_)) + ": ignored";
        });
      } else if (nmt_ == Nmt::operational && r.motion && !guarding_reported_ &&
                 !(r.life_time_ms > 0 && guarding_seen_)) {
        guarding_reported_ = true;
        rep.fire(RuleId::canopen_motion_without_guarding, at, [&] {
          return "RPDO" + std::to_string(r.rpdo) + " writes motion objects while life guarding is off (" +
                 (r.life_time_ms == 0 ? std::string("100Ch × 100Dh = 0 or heartbeat producer on")
                                      : std::string("no guarding RTR since the boot-up")) +
                 ")";
        });
      }
      return;
    case CanKind::guarding: guarding_seen_ = true; return;
    case CanKind::nmt:
    case CanKind::sync:
    case CanKind::other: return;
  }
}

void CanopenRules::on_answer(const SdoAnswer& a) {
  sdo_waiting_ = false;
  // block download end response (scs 5, ss 1) or an abort ends the block transfer
  if (a.byte0 == 0xA1 || a.byte0 == 0x80) block_download_ = false;
}

void CanopenRules::on_mapping(const PdoMappingWrite& m, const At& at, Reporter& rep) {
  if (!m.pdo_valid || m.origin == od::Origin::internal) return;
  rep.fire(RuleId::canopen_pdo_mapping_while_valid, at, [&] {
    char buf[96];
    const bool rx = m.mapping_index < 0x1A00;
    std::snprintf(buf, sizeof buf, "%04Xh.%02X written while %s%u is valid (result 0x%08X)", m.mapping_index, m.sub,
                  rx ? "RPDO" : "TPDO", static_cast<unsigned>((m.mapping_index & 0x01FF) + 1),
                  static_cast<unsigned>(od::to_u32(m.result)));
    return std::string(buf);
  });
}

}  // namespace mcemu::lint
