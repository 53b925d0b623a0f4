// libarmature-client: every Armature RPC from C++, with a deadline on every
// call. Failures throw armature::client::ClientError carrying the gRPC status.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>

#include <grpcpp/grpcpp.h>

#include "armature/v1/assets.grpc.pb.h"
#include "armature/v1/authoring.grpc.pb.h"
#include "armature/v1/deform.grpc.pb.h"
#include "armature/v1/ik.grpc.pb.h"
#include "armature/v1/meshes.grpc.pb.h"
#include "armature/v1/poses.grpc.pb.h"

namespace armature::client {

class ClientError : public std::runtime_error {
 public:
  explicit ClientError(const grpc::Status& status)
      : std::runtime_error(status.error_message()), code_(status.error_code()) {}
  grpc::StatusCode code() const { return code_; }

 private:
  grpc::StatusCode code_;
};

struct ClientOptions {
  std::string target = "localhost:50051";       // host:port
  std::chrono::milliseconds timeout{30000};     // deadline of unary calls
  std::chrono::milliseconds stream_timeout{0};  // deadline of streams; 0 = none
  std::string token;                            // sent as "authorization: Bearer <token>" when set
  std::string ca_file;                          // use TLS, trusting this CA (PEM)
  int max_message_bytes = 64 << 20;
  size_t upload_chunk_bytes = 1 << 20;

  // From ARMATURE_SERVER, ARMATURE_TOKEN and ARMATURE_CA_FILE when set.
  static ClientOptions FromEnvironment();
};

// A file to upload: the main file, and for a .gltf its external resources.
struct UploadFile {
  std::string filename;
  std::string bytes;
};

// An open bidirectional session (IK or deformation): each message is sent
// and its answer awaited, in turn. One thread at a time; the Client must
// outlive it. Throws ClientError when the server ends the session with an
// error.
template <class RequestT, class ResponseT>
class Session {
 public:
  using Request = RequestT;
  using Response = ResponseT;

  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  ~Session();  // cancels the session unless Close() ended it

  // The answer to the last message (after opening: to the start message).
  const Response& last() const { return last_; }
  // Sends one message and waits for its answer.
  const Response& Send(const Request& message);
  // Ends the session; throws ClientError if the server ended it with an error.
  void Close();

 protected:
  friend class Client;
  explicit Session(const char* what) : what_(what) {}
  [[noreturn]] void Fail();  // the stream broke: finishes it and throws its status

  const char* what_;  // "IK session", for messages
  std::unique_ptr<grpc::ClientContext> context_;
  std::unique_ptr<grpc::ClientReaderWriter<Request, Response>> stream_;
  Response last_;
  bool closed_ = false;
};

// An IK session (Client::OpenIkSession): each message sends new targets and
// gets the pose that reaches them, solved from the last one.
class IkSession : public Session<v1::IkSessionRequest, v1::SolveIkResponse> {
 public:
  // Moves effector `effector`'s target position (its index in the start request).
  const v1::SolveIkResponse& MoveTarget(int effector, double x, double y, double z);

 private:
  friend class Client;
  IkSession() : Session("IK session") {}
};

// A deformation (drag) session (Client::OpenDeformSession): the server
// factors the start's constraints once; each move sends the handle positions
// and gets every vertex position back.
class DeformSession : public Session<v1::DeformSessionRequest, v1::DeformResponse> {
 public:
  // x, y, z per handle, in the start's handle_indices order.
  const v1::DeformResponse& Move(std::span<const double> handle_positions);

 private:
  friend class Client;
  DeformSession() : Session("deformation session") {}
};

class Client {
 public:
  explicit Client(ClientOptions options = ClientOptions::FromEnvironment());
  Client(std::shared_ptr<grpc::Channel> channel, ClientOptions options);

  // Imports a file from disk; the files a .gltf's buffer uris name are
  // uploaded too, only from its folder or subfolders unless
  // `allow_outside_resources` (INVALID_ARGUMENT naming the uri otherwise).
  // `format` (bvh, gltf, glb, obj, fbx) overrides what the server would detect
  // from the file name or content. `precision` (ImportAssetRequest.precision):
  // "exact", a bound in centimetres ("0.01"), or empty for the server's default.
  v1::ImportAssetResponse ImportFile(const std::filesystem::path& path, const std::string& name = "",
                                     bool replace = false, bool allow_outside_resources = false,
                                     const std::string& format = "", const std::string& precision = "");
  v1::ImportAssetResponse Import(const UploadFile& main, const std::string& name = "", const std::string& format = "",
                                 bool replace = false, const std::vector<UploadFile>& resources = {},
                                 const std::string& precision = "");
  v1::ListAssetsResponse ListAssets();
  v1::AssetInfo GetAsset(const std::string& name);
  v1::AssetInfo DeleteAsset(const std::string& name);
  v1::ListClipsResponse ListClips();
  v1::ClipInfo GetClip(const std::string& clip);
  v1::ListSkeletonsResponse ListSkeletons();
  v1::Skeleton GetSkeleton(const std::string& skeleton);
  // format: "bvh" (default when empty), "glb" or "gltf"; with_meshes: glTF only.
  v1::ExportClipResponse ExportClip(const std::string& clip, const std::string& format = "", bool with_meshes = false);

  v1::EvaluateClipResponse EvaluateClip(const v1::EvaluateClipRequest& request);
  // A motion (clips composed in layers) at one or many times.
  v1::EvaluateMotionResponse EvaluateMotion(const v1::EvaluateMotionRequest& request);
  // Calls `on_frame` for each frame until the stream ends or it returns false
  // (which cancels the stream).
  void StreamClip(const v1::StreamClipRequest& request, const std::function<bool(const v1::PoseFrame&)>& on_frame);
  v1::ComputeFkResponse ComputeFk(const v1::ComputeFkRequest& request);

  // Inverse kinematics. An unreachable target is not an error: converged() is false.
  v1::SolveIkResponse SolveIk(const v1::SolveIkRequest& request);
  // Opens an IK session and solves `start`; its answer is last(). The
  // session's deadline is ClientOptions::stream_timeout.
  std::unique_ptr<IkSession> OpenIkSession(const v1::SolveIkRequest& start);

  // Mesh editing (Laplacian / ARAP): one edit, every vertex position back.
  v1::DeformResponse Deform(const v1::DeformRequest& request);
  // Opens a drag session: the server factors `start` once and answers with
  // the rest shape (last()). The session's deadline is ClientOptions::stream_timeout.
  std::unique_ptr<DeformSession> OpenDeformSession(const v1::DeformSessionStart& start);

  v1::ListMeshesResponse ListMeshes();
  v1::MeshInfo GetMesh(const std::string& mesh);
  v1::MeshGeometry GetMeshGeometry(const std::string& mesh);
  // Material `material` of the mesh (MeshGeometry.materials), and one of its
  // images' stored bytes with their MIME type.
  v1::Material GetMaterial(const std::string& mesh, int material);
  v1::MaterialImage GetMaterialImage(const std::string& mesh, int material, int image);
  v1::SkinMeshResponse SkinMesh(const v1::SkinMeshRequest& request);
  // As StreamClip: `on_frame` per skinned frame until the end or it returns false.
  void StreamSkinnedMesh(const v1::StreamSkinnedMeshRequest& request,
                         const std::function<bool(const v1::SkinnedMeshFrame&)>& on_frame);
  v1::EvaluateBlendshapesResponse EvaluateBlendshapes(const v1::EvaluateBlendshapesRequest& request);
  v1::BindMeshResponse BindMesh(const v1::BindMeshRequest& request);

  // AuthoringService. A clip from keys per joint, stored as a new asset.
  v1::CreateClipResponse CreateClip(const v1::CreateClipRequest& request);
  // A clip moved onto another skeleton and stored as a new asset; the answer
  // holds the new clip, its asset, the joint pairs used and the unmapped joints.
  v1::RetargetClipResponse RetargetClip(const v1::RetargetClipRequest& request);

  // grpc.health.v1: true when the server reports SERVING.
  bool Healthy();

  const std::shared_ptr<grpc::Channel>& channel() const { return channel_; }
  const ClientOptions& options() const { return options_; }

  // A context with this client's deadline and credentials, for calls on other stubs.
  void Prepare(grpc::ClientContext& context, bool streaming = false) const;

  // One unary call on any stub with this client's deadline and credentials;
  // throws ClientError on failure. Service-specific clients build on it.
  template <class Stub, class Request, class Response>
  Response Call(grpc::Status (Stub::*method)(grpc::ClientContext*, const Request&, Response*), Stub& stub,
                const Request& request) const;

 private:
  ClientOptions options_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::AssetService::Stub> assets_;
  std::unique_ptr<v1::PoseService::Stub> poses_;
  std::unique_ptr<v1::IkService::Stub> ik_;
  std::unique_ptr<v1::MeshService::Stub> meshes_;
  std::unique_ptr<v1::DeformService::Stub> deform_;
  std::unique_ptr<v1::AuthoringService::Stub> authoring_;

  // Opens `stream` on `session` with this client's stream deadline and sends `first`.
  template <class S, class Open>
  std::unique_ptr<S> OpenSession(std::unique_ptr<S> session, Open open, const typename S::Request& first);
};

// Throws ClientError unless `status` is OK.
void Check(const grpc::Status& status);

// "INVALID_ARGUMENT", "NOT_FOUND", …
const char* StatusCodeName(grpc::StatusCode code);

template <class Stub, class Request, class Response>
Response Client::Call(grpc::Status (Stub::*method)(grpc::ClientContext*, const Request&, Response*), Stub& stub,
                      const Request& request) const {
  grpc::ClientContext context;
  Prepare(context);
  Response response;
  Check((stub.*method)(&context, request, &response));
  return response;
}

}  // namespace armature::client
