// SPDX-License-Identifier: MIT
/// @file The per-frame path compiles and runs with -fno-exceptions -fno-rtti, as controller
/// firmware builds it: the codec and the request handler answer the protocol document's example.
#include <cmmcomp/plugins/can_request_handler.hpp>
#include <cstdio>

#include "can_test_frames.hpp"

int main() {
  using namespace cmmcomp;
  using namespace cmmcomp::plugins::can;
  using cmmcomp::plugins::CanFrameBatch;
  using cmmcomp::plugins::CanRequestHandler;
  compensation::MoveCompensator comp;
  if (comp.publish(0, test::example_model(), test::kExampleModelId) != Status::kOk) return 1;
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
  std::puts("ok");
  return 0;
}
