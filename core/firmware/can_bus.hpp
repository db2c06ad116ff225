// A classic CAN bus shared by the MCUs of a pack's monitor boards (ISO 11898 data
// frames, 11-bit identifiers), as the firmware contract's can_send / can_receive see it.
//
//   frame time   SOF, identifier, RTR, IDE, r0, DLC, data and the CRC-15 with their
//                stuff bits (a complement after five equal bits, counted from the
//                frame's own bits), then CRC delimiter, ACK slot and delimiter, EOF and
//                the 3-bit intermission: (stuffed bits + 13) / bit rate
//   arbitration  queued frames go on the wire one at a time; when the bus is free the
//                lowest identifier among the frames ready wins (then the oldest)
//   delivery     at the end of its transmission into every other node's receive FIFO
//   limits       a node's transmit queue (can_send fails when it is full) and receive
//                FIFO (a frame arriving at a full FIFO is lost and counted)
//
// The nodes' tasks run one after another within a BMS tick (core/sim), so the bus is
// resolved lazily: up to the time a node reads it or the tick's end. A frame sent by a
// node that runs later in the tick reaches an earlier one at its next read.
#pragma once
#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

namespace packsim {

class CanBus {
 public:
  CanBus(int nodes, double bitrate_bps, size_t txQueue = 16, size_t rxFifo = 64);

  int nodes() const { return static_cast<int>(rx_.size()); }
  // Queues a frame of `node` ready at t_s; false when its transmit queue is full.
  bool send(int node, double t_s, uint32_t id, const uint8_t* data, uint8_t len);
  // The oldest frame arrived at `node` by t_s: its length (id, data filled), or -1.
  int receive(int node, double t_s, uint32_t& id, uint8_t* data);
  // Everything that starts before t_s goes on the wire.
  void runUntil(double t_s);

  // A frame of a scripted node (a board alone's vehicle / charger, hardware.can.frames)
  // ready at t_s: no transmit queue limits it.
  void inject(int node, double t_s, uint32_t id, const uint8_t* data, uint8_t len);
  // When the oldest frame in node's receive FIFO arrived, if one has by t_s (+inf: empty).
  double oldestArrived(int node, double t_s);
  // The instant the next frame for node will arrive, as far as the frames queued by t_s
  // decide (+inf: none): the one on the wire, or the next to win arbitration.
  double nextArrival(int node, double t_s);

  // Every frame's transmission from now on (result file /can_trace).
  struct TraceRow {
    double start_s, end_s;  // on the wire: start of frame .. end (delivery)
    int from;
    uint32_t id;
    uint8_t len;
    uint8_t data[8];
    bool lost;              // a receiver's FIFO was full
  };
  void trace(bool on) { tracing_ = on; }
  std::vector<TraceRow> takeTrace() { return std::move(trace_); }

  // Bits one data frame occupies on the wire (stuff bits included, intermission too).
  static int frameBits(uint32_t id, const uint8_t* data, uint8_t len);
  double frameTime_s(uint32_t id, const uint8_t* data, uint8_t len) const { return frameBits(id, data, len) / bitrate_; }

  uint64_t framesSent() const { return sent_; }
  uint64_t framesLost() const { return lost_; }
  double busyTime_s() const { return busy_s_; }

 private:
  struct Frame {
    double ready_s;
    uint64_t seq;
    uint32_t id;
    uint8_t len;
    uint8_t data[8];
    int from;
  };
  struct Arrived {
    double at_s;
    uint32_t id;
    uint8_t len;
    uint8_t data[8];
  };
  double bitrate_;
  size_t txQueue_, rxFifo_;
  std::vector<Frame> pending_;
  std::vector<int> queued_;  // per node: frames in pending_
  std::vector<std::deque<Arrived>> rx_;
  double busFree_s_ = 0.0;
  uint64_t seq_ = 0, sent_ = 0, lost_ = 0;
  double busy_s_ = 0.0;
  bool tracing_ = false;
  std::vector<TraceRow> trace_;
};

}  // namespace packsim
