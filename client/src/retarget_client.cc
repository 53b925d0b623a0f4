#include "armature/retarget_client.h"

namespace armature {

v1::RetargetClipResponse RetargetClip(const Client& client, const v1::RetargetClipRequest& request) {
  auto stub = v1::AuthoringService::NewStub(client.channel());
  return client.Call(&v1::AuthoringService::Stub::RetargetClip, *stub, request);
}

}  // namespace armature
