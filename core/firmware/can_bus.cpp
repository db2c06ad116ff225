#include "core/firmware/can_bus.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace packsim {

CanBus::CanBus(int nodes, double bitrate_bps, size_t txQueue, size_t rxFifo)
    : bitrate_(bitrate_bps), txQueue_(txQueue), rxFifo_(rxFifo), queued_(static_cast<size_t>(nodes), 0),
      rx_(static_cast<size_t>(nodes)) {
  if (nodes < 1 || !(bitrate_bps > 0.0)) throw std::invalid_argument("CanBus: needs nodes and a positive bit rate");
}

namespace {

// Bit stuffing over the frame's bits as they go on the wire: after five equal bits a
// complement bit, which starts a new run.
struct Stuffer {
  int bits = 0, run = 0, last = -1;
  void put(uint32_t v, int n) {
    for (int i = n - 1; i >= 0; --i) {
      const int b = static_cast<int>((v >> i) & 1u);
      ++bits;
      run = b == last ? run + 1 : 1;
      last = b;
      if (run == 5) {
        ++bits;
        last = 1 - b;
        run = 1;
      }
    }
  }
};

// CRC-15 (polynomial 0x4599) over the bits SOF .. data, fed as they go on the wire.
uint32_t crc15(uint32_t crc, uint32_t v, int n) {
  for (int i = n - 1; i >= 0; --i) {
    const uint32_t next = ((v >> i) & 1u) ^ ((crc >> 14) & 1u);
    crc = (crc << 1) & 0x7FFFu;
    if (next) crc ^= 0x4599u;
  }
  return crc;
}

}  // namespace

int CanBus::frameBits(uint32_t id, const uint8_t* data, uint8_t len) {
  // The stuffed part: SOF (0), 11-bit identifier, RTR 0, IDE 0, r0 0, DLC, data, CRC-15.
  // SOF, identifier, RTR/IDE/r0 and DLC are 19 bits: one field.
  const uint32_t head = ((id & 0x7FFu) << 7) | (len & 0x0Fu);
  Stuffer st;
  st.put(head, 19);
  uint32_t crc = crc15(0, head, 19);
  for (uint8_t k = 0; k < len; ++k) {
    st.put(data[k], 8);
    crc = crc15(crc, data[k], 8);
  }
  st.put(crc, 15);
  return st.bits + 1 + 2 + 7 + 3;  // CRC delimiter, ACK slot + delimiter, EOF, intermission
}

bool CanBus::send(int node, double t_s, uint32_t id, const uint8_t* data, uint8_t len) {
  if (static_cast<size_t>(queued_[static_cast<size_t>(node)]) >= txQueue_) return false;
  Frame f{t_s, seq_++, id & 0x7FFu, len, {}, node};
  if (len > 0) std::memcpy(f.data, data, len);
  pending_.push_back(f);
  ++queued_[static_cast<size_t>(node)];
  return true;
}

void CanBus::inject(int node, double t_s, uint32_t id, const uint8_t* data, uint8_t len) {
  Frame f{t_s, seq_++, id & 0x7FFu, len, {}, node};
  if (len > 0) std::memcpy(f.data, data, len);
  pending_.push_back(f);
  ++queued_[static_cast<size_t>(node)];
}

double CanBus::oldestArrived(int node, double t_s) {
  runUntil(t_s);
  const std::deque<Arrived>& q = rx_[static_cast<size_t>(node)];
  return !q.empty() && q.front().at_s <= t_s ? q.front().at_s : std::numeric_limits<double>::infinity();
}

double CanBus::nextArrival(int node, double t_s) {
  runUntil(t_s);
  for (const Arrived& a : rx_[static_cast<size_t>(node)])
    if (a.at_s > t_s) return a.at_s;  // on the wire now
  // The frames not yet started, in the order arbitration would send them.
  std::vector<Frame> left = pending_;
  double busFree = busFree_s_;
  while (!left.empty()) {
    double earliest = left.front().ready_s;
    for (const Frame& f : left) earliest = std::min(earliest, f.ready_s);
    const double start = std::max(busFree, earliest);
    size_t win = left.size();
    for (size_t i = 0; i < left.size(); ++i) {
      const Frame& f = left[i];
      if (f.ready_s > start) continue;
      if (win == left.size() || f.id < left[win].id || (f.id == left[win].id && f.seq < left[win].seq)) win = i;
    }
    busFree = start + frameTime_s(left[win].id, left[win].data, left[win].len);
    if (left[win].from != node) return busFree;
    left.erase(left.begin() + static_cast<long>(win));
  }
  return std::numeric_limits<double>::infinity();
}

void CanBus::runUntil(double t_s) {
  while (!pending_.empty()) {
    double earliest = pending_.front().ready_s;
    for (const Frame& f : pending_) earliest = std::min(earliest, f.ready_s);
    const double start = std::max(busFree_s_, earliest);
    if (start > t_s) return;
    // Arbitration among the frames ready when the bus is free: lowest id, then oldest.
    size_t win = pending_.size();
    for (size_t i = 0; i < pending_.size(); ++i) {
      const Frame& f = pending_[i];
      if (f.ready_s > start) continue;
      if (win == pending_.size() || f.id < pending_[win].id || (f.id == pending_[win].id && f.seq < pending_[win].seq))
        win = i;
    }
    const Frame f = pending_[win];
    pending_.erase(pending_.begin() + static_cast<long>(win));
    --queued_[static_cast<size_t>(f.from)];
    const double dur = frameTime_s(f.id, f.data, f.len);
    busFree_s_ = start + dur;
    busy_s_ += dur;
    ++sent_;
    bool lost = false;
    for (size_t n = 0; n < rx_.size(); ++n) {
      if (static_cast<int>(n) == f.from) continue;
      if (rx_[n].size() >= rxFifo_) {
        ++lost_;
        lost = true;
        continue;
      }
      Arrived a{busFree_s_, f.id, f.len, {}};
      std::memcpy(a.data, f.data, f.len);
      rx_[n].push_back(a);
    }
    if (tracing_) {
      TraceRow row{start, busFree_s_, f.from, f.id, f.len, {}, lost};
      std::memcpy(row.data, f.data, f.len);
      trace_.push_back(row);
    }
  }
}

int CanBus::receive(int node, double t_s, uint32_t& id, uint8_t* data) {
  runUntil(t_s);
  std::deque<Arrived>& q = rx_[static_cast<size_t>(node)];
  if (q.empty() || q.front().at_s > t_s) return -1;
  const Arrived a = q.front();
  q.pop_front();
  id = a.id;
  std::memcpy(data, a.data, a.len);
  return a.len;
}

}  // namespace packsim
