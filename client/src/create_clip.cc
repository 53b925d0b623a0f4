#include "armature/create_clip.h"

namespace armature {

v1::CreateClipResponse CreateClip(const Client& client, const v1::CreateClipRequest& request) {
  auto stub = v1::AuthoringService::NewStub(client.channel());
  return client.Call(&v1::AuthoringService::Stub::CreateClip, *stub, request);
}

}  // namespace armature
