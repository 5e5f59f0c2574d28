// Errors of the host-device link. Each fault has its own kind so callers and tests can tell
// them apart; the message says which stream, where in it and what was expected.
#pragma once

#include <string>

#include "sim/error.hpp"

namespace rheo::link {

enum class LinkFault {
  kBadMagic,        // a frame does not start with the magic word: garbage or lost sync
  kBadVersion,      // a frame of a protocol version this build does not speak
  kBadType,         // unknown frame type, or a type not allowed in this direction
  kOversized,       // payload length above the agreed maximum (or not a whole number of words)
  kBadCrc,          // checksum mismatch: a corrupted byte
  kTruncated,       // the stream ended or stalled in the middle of a frame
  kSequenceGap,     // a frame was lost, repeated or reordered
  kTimeout,         // no frame arrived within the time limit
  kClosed,          // the peer closed the connection (or died) between frames
  kRemoteError,     // the peer reported an error frame
  kBusy,            // the server is serving another host and turned this one away
  kIdleTimeout,     // the server closed the session because the host sent nothing for too long
  kProtocol,        // well-formed frames with unexpected content (e.g. wrong response length)
  kDeviceOverflow,  // the core raised its sticky overflow flags: its numbers are not valid
  kOverLimit,       // a command frame asks the server for more than its limits (frame_budget.hpp)
  kIo,              // an operating-system error on the transport
};

const char* to_string(LinkFault fault);

class LinkError : public Error {
 public:
  LinkError(LinkFault fault, const std::string& what)
      : Error(std::string("link: ") + to_string(fault) + ": " + what), fault_(fault) {}
  LinkFault fault() const { return fault_; }

 private:
  LinkFault fault_;
};

}  // namespace rheo::link
