// The SDO server of the node (slcan-canopen.md §6): expedited, segmented and block (CRC-16) upload
// and download on one server channel, with every protocol abort of §6.9.
//
// Contract (pure, single-threaded):
// - on_request() gets the 8 data bytes of a request (DLC 8 on 1200h.01, PRE-OPERATIONAL or
//   OPERATIONAL: the node filters) and appends the response payloads, if any, to `out`, in the same
//   call. Object access goes through the OD with origin `sdo`; after every OD write the
//   `after_write` callback runs (the server drains drive-core events there, so EMCYs raised by the
//   write are ordered after this response).
// - A download that the OD answers with `pending` (Store/Restore) is answered later: the OD's
//   completion is recorded and the response comes out of the next collect() (§6.1). A client abort
//   or a new initiate cancels only that response.
// - advance() applies the server timeout (§6.8); next_deadline() says when it is due.
// - reset() ends any transfer silently (NMT reset, STOPPED).
// - Fault injection (slcan-canopen.md §11.3) through SdoFaults: `abort` is asked at each phase of
//   a transfer — initiate (the answer to the initiate request), segment (the answer to a segment
//   request of a segmented transfer, a block download's sub-block acknowledgement, a block
//   upload's sub-block), end (the answer that completes the transfer; an expedited transfer's one
//   exchange is its initiate and its end) — and a code it returns is sent as the abort instead of
//   the answer, before the OD is written; `no_reply` is asked for every request that gets an
//   answer (index = the transfer's index) and true swallows that answer, a later Store
//   completion included. Both may be empty.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <variant>
#include <vector>

#include "drive/od/dictionary.hpp"
#include "protocols/canopen/config.hpp"
#include "protocols/canopen/types.hpp"

namespace mcemu::canopen {

enum class SdoFaultPhase : std::uint8_t { initiate, segment, end };

struct SdoFaults {
  std::function<std::optional<std::uint32_t>(std::uint16_t index, std::uint8_t sub, SdoFaultPhase phase)> abort;
  std::function<bool(std::uint16_t index)> no_reply;
};

class SdoServer {
 public:
  SdoServer(od::ObjectDictionary& od, const CanopenConfig& config, std::function<void()> after_write);
  ~SdoServer();
  SdoServer(const SdoServer&) = delete;
  SdoServer& operator=(const SdoServer&) = delete;

  void on_request(const Payload& req, Millis now, std::vector<Payload>& out);
  // Responses of completed pending writes (Store/Restore), if still wanted.
  void collect(Millis now, std::vector<Payload>& out);
  void advance(Millis now, std::vector<Payload>& out);
  std::optional<Millis> next_deadline() const;
  void reset();
  bool idle() const;
  bool has_completions() const;
  // Called when a pending write completes (possibly outside any processing call).
  void set_wake(std::function<void()> wake);
  void set_faults(SdoFaults faults) { faults_ = std::move(faults); }

  // Largest transfer accepted into memory for an entry without a size limit (strings).
  static constexpr std::size_t k_max_transfer = 16u << 20;

 private:
  struct Idle {};
  struct SegUpload {
    std::vector<std::uint8_t> data;
    std::size_t pos = 0;
    int toggle = 0;
  };
  struct SegDownload {
    std::optional<std::size_t> size;
    std::vector<std::uint8_t> data;
    int toggle = 0;
  };
  struct BlockDownload {
    std::optional<std::size_t> size;
    bool crc = false;
    std::vector<std::uint8_t> data;
    int blksize = 127;
    int last_seq = 0;       // last in-order sequence number of the current sub-block
    bool skipping = false;  // an out-of-order segment arrived in this sub-block
    std::size_t segments = 0;
    bool awaiting_end = false;
  };
  struct BlockUpload {
    enum class Phase : std::uint8_t { start, ack, end } phase = Phase::start;
    std::vector<std::uint8_t> data;
    bool crc = false;
    int blksize = 127;
    std::size_t offset = 0;  // first byte of the current sub-block
    int sent = 0;            // segments sent in the current sub-block
    bool sent_last = false;  // the current sub-block holds the last data byte
  };
  struct Pending {
    std::uint64_t serial = 0;
    Payload success{};
    bool silent = false;  // slcan.sdoNoReply: the completion is not answered
  };
  using State = std::variant<Idle, SegUpload, SegDownload, BlockDownload, BlockUpload, Pending>;

  struct Shared;  // completion slot shared with the OD's Done callbacks

  void handle(const Payload& req, Millis now, std::vector<Payload>& out);
  // slcan.sdoAbort at this phase of the current transfer: true = the abort was sent (now idle).
  bool injected_abort(SdoFaultPhase phase, std::vector<Payload>& out);
  void upload_initiate(std::uint16_t index, std::uint8_t sub, Millis now, std::vector<Payload>& out);
  void download_initiate(const Payload& req, std::uint16_t index, std::uint8_t sub, Millis now,
                         std::vector<Payload>& out);
  void block_upload_initiate(const Payload& req, std::uint16_t index, std::uint8_t sub, Millis now,
                             std::vector<Payload>& out);
  void block_download_initiate(const Payload& req, std::uint16_t index, std::uint8_t sub, Millis now,
                               std::vector<Payload>& out);
  void upload_segment(const Payload& req, SegUpload& s, Millis now, std::vector<Payload>& out);
  void download_segment(const Payload& req, SegDownload& s, Millis now, std::vector<Payload>& out);
  void block_download_segment(const Payload& req, BlockDownload& s, Millis now, std::vector<Payload>& out);
  void block_download_end(const Payload& req, BlockDownload& s, std::vector<Payload>& out);
  void block_upload_request(const Payload& req, BlockUpload& s, Millis now, std::vector<Payload>& out);
  void send_sub_block(BlockUpload& s, std::vector<Payload>& out);
  // Writes the data; answers `success` now, or later through the pending state, or aborts.
  void finish_download(std::span<const std::uint8_t> data, od::SdoLength length, const Payload& success,
                       std::vector<Payload>& out);
  void abort(od::AbortCode code, std::vector<Payload>& out);  // with the transfer's index/sub; idle
  void keep_alive(Millis now) { deadline_ = now + config_.sdo_timeout; }
  std::optional<std::size_t> max_size() const;  // entry size for numbers, nullopt for strings

  od::ObjectDictionary& od_;
  const CanopenConfig& config_;
  std::function<void()> after_write_;
  std::shared_ptr<Shared> shared_;
  State state_ = Idle{};
  std::uint16_t index_ = 0;
  std::uint8_t sub_ = 0;
  std::optional<Millis> deadline_;
  std::uint64_t next_serial_ = 1;
  SdoFaults faults_;
};

// Payload helpers shared with the tests.
Payload sdo_abort_payload(std::uint16_t index, std::uint8_t sub, od::AbortCode code);

}  // namespace mcemu::canopen
