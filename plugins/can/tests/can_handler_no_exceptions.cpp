// SPDX-License-Identifier: MIT
/// @file The per-frame path compiles and runs with -fno-exceptions -fno-rtti, as controller
/// firmware builds it: the codec and the request handler answer the protocol document's examples
/// (version 1, and version 2 with WantInterval and response part 3).
#include <cmmcomp/plugins/can_request_handler.hpp>
#include <cstdio>

#include "can_test_frames.hpp"

int main() {
  using namespace cmmcomp;
  using namespace cmmcomp::plugins::can;
  using cmmcomp::plugins::CanFrameBatch;
  using cmmcomp::plugins::CanRequestHandler;
  compensation::MoveCompensator comp;
  if (test::publish_example(comp) != Status::kOk) return 1;
  CanRequestHandler handler(comp, kDefaultBaseId, std::chrono::milliseconds(50));
  RequestFrames request;
  if (encode_request(test::example_move(), kDefaultBaseId, request) != Status::kOk) return 1;
  CanFrameBatch out;
  for (const Frame& f : request) handler.on_frame(f, 0, out);
  DecodedResponse d;
  if (out.size != kResponseParts ||
      !decode_response({out.frames[0], out.frames[1], out.frames[2]}, kDefaultBaseId, d) ||
      d.correction.rae_um != 3.5) {
    std::puts("wrong answer");
    return 1;
  }
  RequestFrames asking;
  if (encode_request(test::example_interval_move(), kDefaultBaseId, asking, nullptr, true) !=
      Status::kOk) {
    return 1;
  }
  CanFrameBatch out2;
  for (const Frame& f : asking) handler.on_frame(f, 1'000'000, out2);
  DecodedResponse d2;
  if (out2.size != kResponseParts + 1u ||
      !decode_response({out2.frames[0], out2.frames[1], out2.frames[2]}, kDefaultBaseId, d2) ||
      !decode_interval(out2.frames[3], kDefaultBaseId, d2) || d2.interval_flags != 0 ||
      d2.correction.u95_um[3] < 0.679 || d2.correction.u95_um[3] > 0.681) {
    std::puts("wrong interval answer");
    return 1;
  }
  std::puts("ok");
  return 0;
}
