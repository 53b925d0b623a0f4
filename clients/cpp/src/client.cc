#include "armature/client.h"

#include <cstdlib>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "gltf_resources.h"
#include "grpc/health/v1/health.grpc.pb.h"

namespace armature::client {
namespace {

std::string ReadFileOrThrow(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ClientError(grpc::Status(grpc::StatusCode::NOT_FOUND, "cannot read " + path.string()));
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::shared_ptr<grpc::Channel> MakeChannel(const ClientOptions& o) {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(o.max_message_bytes);
  args.SetMaxSendMessageSize(o.max_message_bytes);
  std::shared_ptr<grpc::ChannelCredentials> creds = grpc::InsecureChannelCredentials();
  if (!o.ca_file.empty()) {
    grpc::SslCredentialsOptions ssl;
    ssl.pem_root_certs = ReadFileOrThrow(o.ca_file);
    creds = grpc::SslCredentials(ssl);
  }
  return grpc::CreateCustomChannel(o.target, creds, args);
}

}  // namespace

const char* StatusCodeName(grpc::StatusCode code) {
  static const char* const kNames[] = {
      "OK",        "CANCELLED",      "UNKNOWN",           "INVALID_ARGUMENT",   "DEADLINE_EXCEEDED",
      "NOT_FOUND", "ALREADY_EXISTS", "PERMISSION_DENIED", "RESOURCE_EXHAUSTED", "FAILED_PRECONDITION",
      "ABORTED",   "OUT_OF_RANGE",   "UNIMPLEMENTED",     "INTERNAL",           "UNAVAILABLE",
      "DATA_LOSS", "UNAUTHENTICATED"};
  const int i = static_cast<int>(code);
  return i >= 0 && i <= 16 ? kNames[i] : "UNKNOWN";
}

void Check(const grpc::Status& status) {
  if (!status.ok()) throw ClientError(status);
}

ClientOptions ClientOptions::FromEnvironment() {
  ClientOptions o;
  if (const char* s = std::getenv("ARMATURE_SERVER"); s && *s) o.target = s;
  if (const char* s = std::getenv("ARMATURE_TOKEN"); s && *s) o.token = s;
  if (const char* s = std::getenv("ARMATURE_CA_FILE"); s && *s) o.ca_file = s;
  return o;
}

Client::Client(ClientOptions options) : Client(MakeChannel(options), options) {}

Client::Client(std::shared_ptr<grpc::Channel> channel, ClientOptions options)
    : options_(std::move(options)),
      channel_(std::move(channel)),
      assets_(v1::AssetService::NewStub(channel_)),
      poses_(v1::PoseService::NewStub(channel_)),
      ik_(v1::IkService::NewStub(channel_)),
      meshes_(v1::MeshService::NewStub(channel_)),
      deform_(v1::DeformService::NewStub(channel_)),
      authoring_(v1::AuthoringService::NewStub(channel_)) {}

void Client::Prepare(grpc::ClientContext& context, bool streaming) const {
  const auto timeout = streaming ? options_.stream_timeout : options_.timeout;
  if (timeout.count() > 0) context.set_deadline(std::chrono::system_clock::now() + timeout);
  if (!options_.token.empty()) context.AddMetadata("authorization", "Bearer " + options_.token);
}

v1::ImportAssetResponse Client::ImportFile(const std::filesystem::path& path, const std::string& name, bool replace,
                                           bool allow_outside_resources, const std::string& format,
                                           const std::string& precision) {
  UploadFile main{path.filename().string(), ReadFileOrThrow(path)};
  std::vector<UploadFile> resources;
  const bool gltf = format.empty() ? path.extension() == ".gltf" : format == "gltf";
  if (gltf) resources = detail::GltfResources(path, main.bytes, allow_outside_resources);
  return Import(main, name, format, replace, resources, precision);
}

v1::ImportAssetResponse Client::Import(const UploadFile& main, const std::string& name, const std::string& format,
                                       bool replace, const std::vector<UploadFile>& resources,
                                       const std::string& precision) {
  grpc::ClientContext context;
  Prepare(context);
  v1::ImportAssetResponse response;
  auto writer = assets_->ImportAsset(&context, &response);
  const size_t chunk = std::max<size_t>(1, options_.upload_chunk_bytes);
  auto send_file = [&](const UploadFile& file, bool is_main) {
    size_t offset = 0;
    do {
      v1::ImportAssetRequest request;
      if (offset == 0) {
        if (is_main) {
          request.set_filename(file.filename);
          request.set_name(name);
          request.set_format(format);
          request.set_replace(replace);
          request.set_precision(precision);
        } else {
          request.set_resource(file.filename);
        }
      }
      const size_t n = std::min(chunk, file.bytes.size() - offset);
      request.set_data(file.bytes.substr(offset, n));
      offset += n;
      if (!writer->Write(request)) return false;  // the server ended the call early
    } while (offset < file.bytes.size());
    return true;
  };
  if (send_file(main, true))
    for (const UploadFile& r : resources)
      if (!send_file(r, false)) break;
  writer->WritesDone();
  Check(writer->Finish());
  return response;
}

v1::ListAssetsResponse Client::ListAssets() { return Call(&v1::AssetService::Stub::ListAssets, *assets_, {}); }
v1::AssetInfo Client::GetAsset(const std::string& name) {
  v1::GetAssetRequest r;
  r.set_name(name);
  return Call(&v1::AssetService::Stub::GetAsset, *assets_, r);
}
v1::AssetInfo Client::DeleteAsset(const std::string& name) {
  v1::DeleteAssetRequest r;
  r.set_name(name);
  return Call(&v1::AssetService::Stub::DeleteAsset, *assets_, r);
}
v1::ListClipsResponse Client::ListClips() { return Call(&v1::AssetService::Stub::ListClips, *assets_, {}); }
v1::ClipInfo Client::GetClip(const std::string& clip) {
  v1::GetClipRequest r;
  r.set_clip(clip);
  return Call(&v1::AssetService::Stub::GetClip, *assets_, r);
}
v1::ListSkeletonsResponse Client::ListSkeletons() { return Call(&v1::AssetService::Stub::ListSkeletons, *assets_, {}); }
v1::Skeleton Client::GetSkeleton(const std::string& skeleton) {
  v1::GetSkeletonRequest r;
  r.set_skeleton(skeleton);
  return Call(&v1::AssetService::Stub::GetSkeleton, *assets_, r);
}
v1::ExportClipResponse Client::ExportClip(const std::string& clip, const std::string& format, bool with_meshes) {
  v1::ExportClipRequest r;
  r.set_clip(clip);
  r.set_format(format);
  r.set_with_meshes(with_meshes);
  return Call(&v1::AssetService::Stub::ExportClip, *assets_, r);
}
v1::EvaluateClipResponse Client::EvaluateClip(const v1::EvaluateClipRequest& r) {
  return Call(&v1::PoseService::Stub::EvaluateClip, *poses_, r);
}
v1::EvaluateMotionResponse Client::EvaluateMotion(const v1::EvaluateMotionRequest& r) {
  return Call(&v1::PoseService::Stub::EvaluateMotion, *poses_, r);
}
v1::ComputeFkResponse Client::ComputeFk(const v1::ComputeFkRequest& r) {
  return Call(&v1::PoseService::Stub::ComputeFk, *poses_, r);
}

v1::SolveIkResponse Client::SolveIk(const v1::SolveIkRequest& r) {
  return Call(&v1::IkService::Stub::SolveIk, *ik_, r);
}

template <class S, class Open>
std::unique_ptr<S> Client::OpenSession(std::unique_ptr<S> session, Open open, const typename S::Request& first) {
  session->context_ = std::make_unique<grpc::ClientContext>();
  Prepare(*session->context_, true);
  session->stream_ = open(session->context_.get());
  session->Send(first);
  return session;
}

std::unique_ptr<IkSession> Client::OpenIkSession(const v1::SolveIkRequest& start) {
  v1::IkSessionRequest first;
  *first.mutable_start() = start;
  return OpenSession(
      std::unique_ptr<IkSession>(new IkSession()), [this](grpc::ClientContext* c) { return ik_->IkSession(c); }, first);
}

v1::DeformResponse Client::Deform(const v1::DeformRequest& r) {
  return Call(&v1::DeformService::Stub::Deform, *deform_, r);
}

std::unique_ptr<DeformSession> Client::OpenDeformSession(const v1::DeformSessionStart& start) {
  v1::DeformSessionRequest first;
  *first.mutable_start() = start;
  return OpenSession(
      std::unique_ptr<DeformSession>(new DeformSession()),
      [this](grpc::ClientContext* c) { return deform_->DeformSession(c); }, first);
}

template <class Request, class Response>
const Response& Session<Request, Response>::Send(const Request& message) {
  if (closed_)
    throw ClientError(grpc::Status(grpc::StatusCode::FAILED_PRECONDITION, std::string("the ") + what_ + " is closed"));
  if (!stream_->Write(message) || !stream_->Read(&last_)) Fail();
  return last_;
}

template <class Request, class Response>
void Session<Request, Response>::Fail() {
  closed_ = true;
  grpc::Status status = stream_->Finish();
  if (status.ok())
    status =
        grpc::Status(grpc::StatusCode::UNKNOWN, std::string("the server ended the ") + what_ + " without an answer");
  throw ClientError(status);
}

template <class Request, class Response>
void Session<Request, Response>::Close() {
  if (closed_) return;
  closed_ = true;
  stream_->WritesDone();
  Response extra;
  while (stream_->Read(&extra)) {}
  Check(stream_->Finish());
}

template <class Request, class Response>
Session<Request, Response>::~Session() {
  if (closed_ || !stream_) return;
  context_->TryCancel();
  Response extra;
  while (stream_->Read(&extra)) {}
  (void)stream_->Finish();
}

template class Session<v1::IkSessionRequest, v1::SolveIkResponse>;
template class Session<v1::DeformSessionRequest, v1::DeformResponse>;

const v1::SolveIkResponse& IkSession::MoveTarget(int effector, double x, double y, double z) {
  v1::IkSessionRequest message;
  v1::IkTargetUpdate* target = message.add_targets();
  target->set_effector(effector);
  for (double v : {x, y, z}) target->add_target_position(v);
  return Send(message);
}

const v1::DeformResponse& DeformSession::Move(std::span<const double> handle_positions) {
  v1::DeformSessionRequest message;
  message.mutable_move()->mutable_positions()->Add(handle_positions.begin(), handle_positions.end());
  return Send(message);
}

namespace {
// Reads a server stream into `on_frame` until it ends or `on_frame` returns
// false (then cancels it, draining what is in flight).
template <class Frame>
void ReadStream(grpc::ClientContext& context, grpc::ClientReader<Frame>& reader,
                const std::function<bool(const Frame&)>& on_frame) {
  Frame frame;
  while (reader.Read(&frame)) {
    if (!on_frame(frame)) {
      context.TryCancel();
      while (reader.Read(&frame)) {}
      reader.Finish();
      return;
    }
  }
  Check(reader.Finish());
}
}  // namespace

void Client::StreamClip(const v1::StreamClipRequest& request,
                        const std::function<bool(const v1::PoseFrame&)>& on_frame) {
  grpc::ClientContext context;
  Prepare(context, true);
  ReadStream(context, *poses_->StreamClip(&context, request), on_frame);
}

v1::ListMeshesResponse Client::ListMeshes() {
  return Call(&v1::MeshService::Stub::ListMeshes, *meshes_, v1::ListMeshesRequest());
}
v1::MeshInfo Client::GetMesh(const std::string& mesh) {
  v1::GetMeshRequest r;
  r.set_mesh(mesh);
  return Call(&v1::MeshService::Stub::GetMesh, *meshes_, r);
}
v1::MeshGeometry Client::GetMeshGeometry(const std::string& mesh) {
  v1::GetMeshGeometryRequest r;
  r.set_mesh(mesh);
  return Call(&v1::MeshService::Stub::GetMeshGeometry, *meshes_, r);
}
v1::Material Client::GetMaterial(const std::string& mesh, int material) {
  v1::GetMaterialRequest r;
  r.set_mesh(mesh);
  r.set_material(material);
  return Call(&v1::MeshService::Stub::GetMaterial, *meshes_, r);
}
v1::MaterialImage Client::GetMaterialImage(const std::string& mesh, int material, int image) {
  v1::GetMaterialImageRequest r;
  r.set_mesh(mesh);
  r.set_material(material);
  r.set_image(image);
  return Call(&v1::MeshService::Stub::GetMaterialImage, *meshes_, r);
}
v1::SkinMeshResponse Client::SkinMesh(const v1::SkinMeshRequest& r) {
  return Call(&v1::MeshService::Stub::SkinMesh, *meshes_, r);
}
void Client::StreamSkinnedMesh(const v1::StreamSkinnedMeshRequest& request,
                               const std::function<bool(const v1::SkinnedMeshFrame&)>& on_frame) {
  grpc::ClientContext context;
  Prepare(context, true);
  ReadStream(context, *meshes_->StreamSkinnedMesh(&context, request), on_frame);
}
v1::EvaluateBlendshapesResponse Client::EvaluateBlendshapes(const v1::EvaluateBlendshapesRequest& r) {
  return Call(&v1::MeshService::Stub::EvaluateBlendshapes, *meshes_, r);
}
v1::BindMeshResponse Client::BindMesh(const v1::BindMeshRequest& r) {
  return Call(&v1::MeshService::Stub::BindMesh, *meshes_, r);
}

v1::CreateClipResponse Client::CreateClip(const v1::CreateClipRequest& r) {
  return Call(&v1::AuthoringService::Stub::CreateClip, *authoring_, r);
}
v1::RetargetClipResponse Client::RetargetClip(const v1::RetargetClipRequest& r) {
  return Call(&v1::AuthoringService::Stub::RetargetClip, *authoring_, r);
}

bool Client::Healthy() {
  auto stub = grpc::health::v1::Health::NewStub(channel_);
  grpc::ClientContext context;
  Prepare(context);
  grpc::health::v1::HealthCheckRequest request;
  grpc::health::v1::HealthCheckResponse response;
  const grpc::Status status = stub->Check(&context, request, &response);
  return status.ok() && response.status() == grpc::health::v1::HealthCheckResponse::SERVING;
}

}  // namespace armature::client
