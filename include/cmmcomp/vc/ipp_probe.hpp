// SPDX-License-Identifier: MIT
/// @file The virtual controller's touches from a machine behind an I++ DME server (the twin's
/// `cmmcomp-sim serve-ipp`, or any I++ server), through the project's client
/// (docs/protocol-ippdme.md).
///
/// Each touch is the block measure's plan.ipp writes for one point: SetProp of GoToPar, a GoTo to
/// the start PD + AD out along +X, a GoTo to the pre-hit point AD out, SetProp of PtMeasPar, and
/// `PtMeas(X(x0), Y(y), Z(0), IJK(1, 0, 0))`: the approach runs along −X, and the server's
/// reported X is x0 + RAE (the project's sign, docs/compensator.md), so RAE = (X − x0) · 1000 µm,
/// to the 1e-3 µm the I++ numbers carry. The server draws its own noise (its n-th point): the
/// `index` a caller passes selects nothing here. Setup-level code: throws cmmcomp::Error naming
/// the server and the command when a transaction fails or times out.
///
/// Through the compensating proxy (cmmcomp-agent --ipp-proxy) the reported X is corrected and the
/// line carries `CmmcompCorrection(dx, dy, dz)`: the probe takes the machine's touch as X − dx
/// (what the server reported) and keeps the proxy's correction as an agent's answer, which
/// IppProxySource hands to the length test.
#pragma once

#include <cmmcomp/ipp/client.hpp>
#include <cmmcomp/vc/correction_source.hpp>
#include <cmmcomp/vc/twin_probe.hpp>
#include <cstdint>
#include <memory>
#include <string>

namespace cmmcomp::vc {

class IppProbe final : public TouchErrorModel {
 public:
  /// Connects and starts a session (Error when it cannot); `x0_mm` is the probed face's X.
  IppProbe(const std::string& host,
           std::uint16_t port,
           double x0_mm = 0.0,
           double timeout_s = 30.0);
  /// Ends the session (errors ignored).
  ~IppProbe() override;
  double rae_um(const ProbeSetting& s, double y_mm, std::uint64_t index) override;

  /// Probes the point of `move` (its setting, its Y) now and returns the proxy's correction as
  /// an answer (not usable when the line carries no correction, or its flags say so); the next
  /// rae_um of the same setting and Y returns this touch instead of probing again.
  Answer probe_ahead(const compensation::MoveRequest& move);

 private:
  /// Runs one point's block; the server's touch [µm] and the proxy's answer.
  double probe(const ProbeSetting& s, double y_mm, Answer& proxy);
  /// Runs `command`; throws Error with the server's error when it is not ok.
  ipp::Transaction run(const std::string& command);
  std::unique_ptr<ipp::Client> client_;
  std::string where_;
  double x0_mm_ = 0;
  double timeout_s_ = 30;
  bool ahead_ = false;  ///< a touch probed ahead waits for its rae_um
  ProbeSetting ahead_setting_;
  double ahead_y_mm_ = 0, ahead_rae_um_ = 0;
};

/// The compensating proxy in front of an IppProbe's server as the length test's agent: each
/// question probes the point through the proxy (IppProbe::probe_ahead) and answers with the
/// correction the proxy applied to it.
class IppProxySource final : public CorrectionSource {
 public:
  IppProxySource(IppProbe& probe, std::string label, std::string where)
      : probe_(probe), label_(std::move(label)), where_(std::move(where)) {}
  Answer ask(const compensation::MoveRequest& move) override { return probe_.probe_ahead(move); }
  const std::string& label() const noexcept override { return label_; }
  const std::string& where() const noexcept override { return where_; }

 private:
  IppProbe& probe_;
  std::string label_, where_;
};

}  // namespace cmmcomp::vc
