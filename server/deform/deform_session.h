// One drag session's logic, without gRPC: the first message (`start`) sets
// up the deformer (a factorization: the session reactor runs it off gRPC's
// callback threads) and is answered with the rest shape; each `move` is a
// back-substitution answered in order. The solver lives exactly as long as
// the session. Run by SessionReactor<DeformSession>.
#pragma once

#include <cstdint>
#include <optional>

#include "armature/v1/deform.pb.h"
#include "server/assets/catalog.h"
#include "server/deform/mesh_deformer.h"
#include "server/rpc/call_stop.h"
#include "server/rpc/limits.h"
#include "server/rpc/streams/session_kind.h"

namespace armature::server {

class DeformSession {
 public:
  using Request = v1::DeformSessionRequest;
  using Response = v1::DeformResponse;
  static constexpr SessionKind kKind = SessionKind::kDeform;
  static constexpr const char* kName = "DeformSession";

  DeformSession(CatalogSource catalog, const Limits& limits) : catalog_(std::move(catalog)), limits_(limits) {}

  // The answer's index is 0 for the start, then the move's number (1, 2, …).
  Status Start(const CallStop& call, const Request& first, Response* response);
  Status Answer(const Request& next, Response* response);

 private:
  CatalogSource catalog_;
  const Limits& limits_;
  uint64_t moves_ = 0;
  std::optional<MeshDeformer> deformer_;
};

}  // namespace armature::server
