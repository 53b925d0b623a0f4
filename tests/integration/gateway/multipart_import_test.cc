// POST /v1/assets:import with multipart/form-data, the way browsers send
// files: a multi-file .gltf and its .bin buffers as file parts, sent with
// httplib's multipart client, must give the same asset as the gRPC import;
// every error names the part, the uri or the field at fault.
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "armature/engine/io/demo_character.h"
#include "support/client_helpers.h"
#include "support/data_dir_check.h"
#include "support/metrics_scrape.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

constexpr char kImport[] = "/v1/assets:import";

httplib::Client Http(const ServerProcess& server) {
  httplib::Client http("127.0.0.1", server.http_port());
  http.set_read_timeout(60);
  http.set_write_timeout(60);
  return http;
}

httplib::Result PostForm(httplib::Client& http, const httplib::MultipartFormDataItems& form,
                         const httplib::Headers& headers = {}) {
  return http.Post(kImport, headers, form);
}

httplib::MultipartFormData File(const std::string& filename, const std::string& content) {
  return {"files", content, filename, "application/octet-stream"};
}

httplib::MultipartFormData Field(const std::string& name, const std::string& value) { return {name, value, "", ""}; }

// An error answer: its HTTP status, gRPC code and a fragment of its message.
void ExpectError(const httplib::Result& r, int http_status, grpc::StatusCode code, const std::string& fragment) {
  ASSERT_TRUE(r) << "no response: " << httplib::to_string(r.error());
  EXPECT_EQ(r->status, http_status) << r->body;
  const json j = json::parse(r->body, nullptr, false);
  ASSERT_TRUE(j.is_object()) << r->body;
  EXPECT_EQ(j.value("code", -1), static_cast<int>(code)) << r->body;
  EXPECT_NE(j.value("message", std::string()).find(fragment), std::string::npos)
      << "message lacks '" << fragment << "': " << r->body;
}

// The sample's .gltf and every file beside it that one of its buffer uris names.
struct GltfFiles {
  fs::path gltf;
  std::vector<std::pair<std::string, std::string>> resources;  // uri → bytes
};

GltfFiles ReadSample(const fs::path& gltf) {
  GltfFiles out{gltf, {}};
  const json doc = json::parse(ReadFile(gltf));
  for (const auto& buffer : doc.at("buffers")) {
    const std::string uri = buffer.value("uri", "");
    if (!uri.empty() && uri.rfind("data:", 0) != 0) out.resources.emplace_back(uri, ReadFile(gltf.parent_path() / uri));
  }
  return out;
}

// What the asset holds, without its name and upload time: the parts' names relative to the asset.
json Contents(const v1::AssetInfo& asset) {
  auto relative = [&](const std::string& part) { return part.substr(asset.name().size()); };
  json j = {{"format", asset.format()}, {"filename", asset.filename()}, {"size", asset.size_bytes()}};
  for (const auto& m : asset.meshes()) j["meshes"].push_back(json::array({relative(m.name()), m.vertex_count()}));
  for (const auto& c : asset.clips()) j["clips"].push_back(json::array({relative(c.name()), c.duration()}));
  for (const auto& s : asset.skeletons()) j["skeletons"].push_back(json::array({relative(s.name()), s.joint_count()}));
  return j;
}

class MultipartImport : public ::testing::Test {
 protected:
  TempDir data_;
};

// Two real multi-file samples (SimpleMorph has two .bin buffers) over REST
// and over gRPC: the same listing, and mesh geometry equal to the bit.
TEST_F(MultipartImport, MultiFileGltfGivesTheSameAssetAsGrpc) {
  ServerProcess server(data_.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  auto http = Http(server);
  int compared = 0;
  std::string available;  // a sample found, for the checks after the loop
  for (const std::string relative :
       {"gltf/SimpleMorph/SimpleMorph.gltf", "gltf/AnimatedMorphCube/AnimatedMorphCube.gltf"}) {
    const std::string path = SharedData(relative);
    if (path.empty()) {
      std::printf("SKIP part: %s not found in the shared data\n", relative.c_str());
      continue;
    }
    available = path;
    const GltfFiles sample = ReadSample(path);
    ASSERT_FALSE(sample.resources.empty()) << relative << " has no external buffer";
    const std::string stem = sample.gltf.stem().string();

    // Resources first and the .gltf last: the order of the parts does not matter.
    httplib::MultipartFormDataItems form;
    for (const auto& [uri, bytes] : sample.resources) form.push_back(File(uri, bytes));
    form.push_back({"files", ReadFile(sample.gltf), sample.gltf.filename().string(), "model/gltf+json"});
    // Without a `name` field the asset is named after the .gltf.
    const auto r = PostForm(http, form);
    ASSERT_TRUE(r) << httplib::to_string(r.error());
    ASSERT_EQ(r->status, 200) << r->body;
    const json rest = json::parse(r->body);
    EXPECT_EQ(rest["asset"]["name"], stem) << r->body;
    EXPECT_EQ(rest["asset"]["filename"], sample.gltf.filename().string());

    // The same sample over gRPC, under another name.
    const std::string grpc_name = stem + "_grpc";
    const auto grpc_import = client.ImportFile(sample.gltf, grpc_name);
    const v1::AssetInfo over_rest = client.GetAsset(stem);
    EXPECT_EQ(Contents(over_rest), Contents(grpc_import.asset()));
    ASSERT_EQ(over_rest.meshes_size(), grpc_import.asset().meshes_size());
    ASSERT_GE(over_rest.meshes_size(), 1);
    for (int i = 0; i < over_rest.meshes_size(); ++i) {
      const auto a = client.GetMeshGeometry(over_rest.meshes(i).name());
      const auto b = client.GetMeshGeometry(grpc_import.asset().meshes(i).name());
      EXPECT_GT(a.vertex_count(), 0);
      EXPECT_EQ(a.vertex_count(), b.vertex_count());
      EXPECT_EQ(std::vector<float>(a.positions().begin(), a.positions().end()),
                std::vector<float>(b.positions().begin(), b.positions().end()));
      EXPECT_EQ(std::vector<float>(a.normals().begin(), a.normals().end()),
                std::vector<float>(b.normals().begin(), b.normals().end()));
      EXPECT_EQ(std::vector<uint32_t>(a.triangles().begin(), a.triangles().end()),
                std::vector<uint32_t>(b.triangles().begin(), b.triangles().end()));
      std::printf("%s: mesh %s, %d vertices, %d triangles, same over REST and gRPC\n", relative.c_str(),
                  over_rest.meshes(i).name().c_str(), a.vertex_count(), a.triangles_size() / 3);
    }
    ++compared;
  }
  if (compared == 0)
    GTEST_SKIP() << "no multi-file glTF sample in the shared data (gltf/SimpleMorph, gltf/AnimatedMorphCube)";

  // An explicit name, and `replace` as a form field, reach the import.
  const GltfFiles sample = ReadSample(available);
  httplib::MultipartFormDataItems form = {File(sample.gltf.filename().string(), ReadFile(sample.gltf)),
                                          Field("name", "renamed")};
  for (const auto& [uri, bytes] : sample.resources) form.push_back(File(uri, bytes));
  const auto named = PostForm(http, form);
  ASSERT_EQ(named->status, 200) << named->body;
  EXPECT_EQ(json::parse(named->body)["asset"]["name"], "renamed");
  ExpectError(PostForm(http, form), 409, grpc::StatusCode::ALREADY_EXISTS, "renamed");
  form.push_back(Field("replace", "true"));
  EXPECT_EQ(PostForm(http, form)->status, 200);
  EXPECT_EQ(AssetNames(client).count("renamed"), 1u);
}

class MultipartImportErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    auto glb = MakeDemoCharacterGlb();
    ASSERT_TRUE(glb.ok()) << glb.status().message();
    character_ = SplitGlb(*glb, "body.bin");
  }
  TempDir data_;
  SplitGltf character_;
};

TEST_F(MultipartImportErrors, EachNamesTheProblem) {
  ServerProcess server(data_.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  auto http = Http(server);

  // The demo character split into a .gltf and its buffer imports...
  const auto ok = PostForm(http, {File("character.gltf", character_.gltf), File("body.bin", character_.bin)});
  ASSERT_EQ(ok->status, 200) << ok->body;
  EXPECT_EQ(json::parse(ok->body)["asset"]["name"], "character");

  // ...but not without the buffer its uri names.
  ExpectError(PostForm(http, {File("lonely.gltf", character_.gltf)}), 400, grpc::StatusCode::INVALID_ARGUMENT,
              "'body.bin'");
  // Nor with the buffer under another name.
  ExpectError(PostForm(http, {File("misnamed.gltf", character_.gltf), File("other.bin", character_.bin)}), 400,
              grpc::StatusCode::INVALID_ARGUMENT, "'body.bin'");
  // A second .gltf part.
  ExpectError(PostForm(http, {File("a.gltf", character_.gltf), File("body.bin", character_.bin),
                              File("b.GLTF", character_.gltf)}),
              400, grpc::StatusCode::INVALID_ARGUMENT, "'a.gltf' and 'b.GLTF' are both .gltf files");
  // Two files of one name.
  ExpectError(PostForm(http, {File("c.gltf", character_.gltf), File("body.bin", character_.bin),
                              File("body.bin", character_.bin)}),
              400, grpc::StatusCode::INVALID_ARGUMENT, "two files are named 'body.bin'");
  // Several files and no .gltf.
  ExpectError(PostForm(http, {File("x.bin", "1"), File("y.bin", "2")}), 400, grpc::StatusCode::INVALID_ARGUMENT,
              "no .gltf among them");
  // No file at all.
  ExpectError(PostForm(http, {Field("name", "nothing")}), 400, grpc::StatusCode::INVALID_ARGUMENT, "no file part");
  // A field the parts set, and a field the request does not have.
  ExpectError(PostForm(http, {File("d.gltf", character_.gltf), File("body.bin", character_.bin),
                              Field("resource", "body.bin")}),
              400, grpc::StatusCode::INVALID_ARGUMENT, "'resource'");
  ExpectError(
      PostForm(http, {File("e.gltf", character_.gltf), File("body.bin", character_.bin), Field("colour", "red")}), 400,
      grpc::StatusCode::INVALID_ARGUMENT, "form field 'colour'");
  // A bad value is named as a form field too.
  ExpectError(
      PostForm(http, {File("f.gltf", character_.gltf), File("body.bin", character_.bin), Field("replace", "maybe")}),
      400, grpc::StatusCode::INVALID_ARGUMENT, "form field");

  // A single file part needs no .gltf: a BVH from a browser's file input.
  const auto bvh = PostForm(http, {File("arm.bvh", kArmBvh)});
  ASSERT_EQ(bvh->status, 200) << bvh->body;
  EXPECT_EQ(json::parse(bvh->body)["asset"]["name"], "arm");

  // A form where JSON is expected: 415, before the body is read.
  ExpectError(http.Post("/v1/clips/arm.arm:evaluate", httplib::MultipartFormDataItems{Field("times", "0")}), 415,
              grpc::StatusCode::INVALID_ARGUMENT, "does not take multipart/form-data");
  // A malformed form: the boundary in the header is not the body's.
  ExpectError(http.Post(kImport,
                        "--other\r\nContent-Disposition: form-data; name=\"files\"; filename=\"x.bvh\"\r\n\r\n" +
                            std::string(kArmBvh) + "\r\n--other--\r\n",
                        "multipart/form-data; boundary=expected"),
              400, grpc::StatusCode::INVALID_ARGUMENT, "malformed");

  // None of the refused uploads left an asset or a file behind.
  EXPECT_EQ(AssetNames(client), (std::set<std::string>{"character", "arm"}));
  EXPECT_TRUE(LeftoverFiles(data_.path()).empty());
}

// --max-upload-mb counts every part, every filename and every field name;
// the part that crosses the limit is named.
TEST_F(MultipartImportErrors, TheLimitCountsEveryPartAndNameAndNamesThePart) {
  constexpr int64_t kLimit = 64 << 10;  // --max-upload-mb 0.0625
  // --max-request-kb 1 so the HTTP server's own body cap is the upload limit's (plus the form's framing).
  ServerProcess server(data_.path(), {"--no-demo", "--max-upload-mb", "0.0625", "--max-request-kb", "1"});
  client::Client client(OptionsFor(server));
  auto http = Http(server);

  // Each part fits, together they do not: the second is named.
  const std::string half(kLimit / 2 + 1, 'x');
  ExpectError(PostForm(http, {File("g.gltf", half), File("big.bin", half)}), 413, grpc::StatusCode::RESOURCE_EXHAUSTED,
              "form part 'big.bin' (field 'files')");
  // The contents fit with 100 bytes to spare, the names do not.
  const std::string bvh = std::string(kArmBvh) + std::string(kLimit - 100 - std::string(kArmBvh).size(), '\n');
  const std::string long_name = std::string(120, 'n') + ".bvh";
  ExpectError(PostForm(http, {File(long_name, bvh)}), 413, grpc::StatusCode::RESOURCE_EXHAUSTED, "--max-upload-mb");
  // With a short name the same content imports: the names made the difference. The
  // body on the wire (boundaries, part headers) is over the limit: framing does not count.
  const std::string boundary = "fits-the-limit";
  const std::string wire = "--" + boundary +
                           "\r\nContent-Disposition: form-data; name=\"files\"; filename=\"short.bvh\"\r\n"
                           "Content-Type: application/octet-stream\r\n\r\n" +
                           bvh + "\r\n--" + boundary + "--\r\n";
  EXPECT_GT(wire.size(), static_cast<size_t>(kLimit)) << "the test needs a body over the limit";
  const auto fits = http.Post(kImport, wire, "multipart/form-data; boundary=" + boundary);
  ASSERT_EQ(fits->status, 200) << fits->body;
  // Many tiny parts are capped by count, whatever their size.
  httplib::MultipartFormDataItems many;
  for (int i = 0; i <= 1024; ++i) many.push_back(File("p" + std::to_string(i) + ".bin", ""));
  ExpectError(PostForm(http, many), 413, grpc::StatusCode::RESOURCE_EXHAUSTED, "more than 1024 parts");
  // The same two files over gRPC are refused by the same limit.
  EXPECT_EQ(CodeOf([&] {
              client.Import({"h.gltf", half}, "", "", false, {{"big.bin", half}});
            }),
            grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_EQ(AssetNames(client), (std::set<std::string>{"short"}));
}

// The token is checked before the form is read, and form imports are counted
// as ImportAsset calls, as over gRPC.
TEST_F(MultipartImportErrors, NeedsTheTokenAndIsCounted) {
  TempDir secrets;
  const fs::path token_file = WriteTemp(secrets, "token", "form-token-1\n");
  ServerProcess server(data_.path(), {"--no-demo", "--auth-token-file", token_file.string()});
  auto http = Http(server);
  const httplib::MultipartFormDataItems form = {File("tok.gltf", character_.gltf), File("body.bin", character_.bin)};
  ExpectError(PostForm(http, form), 401, grpc::StatusCode::UNAUTHENTICATED, "");
  const auto ok = PostForm(http, form, {{"Authorization", "Bearer form-token-1"}});
  ASSERT_EQ(ok->status, 200) << ok->body;
  ExpectError(PostForm(http, {File("tok2.gltf", character_.gltf)}, {{"Authorization", "Bearer form-token-1"}}), 400,
              grpc::StatusCode::INVALID_ARGUMENT, "'body.bin'");
  const auto metrics = ParseSamples(http.Get("/metrics", {{"Authorization", "Bearer form-token-1"}})->body);
  const std::string method = "armature.v1.AssetService/ImportAsset";
  EXPECT_EQ(metrics.at("armature_rpc_requests_total{method=\"" + method + "\",code=\"OK\"}"), 1);
  EXPECT_EQ(metrics.at("armature_rpc_requests_total{method=\"" + method + "\",code=\"INVALID_ARGUMENT\"}"), 1);
}

// /openapi.json offers the form beside the raw body, on the import only.
TEST_F(MultipartImport, OpenApiOffersTheFormOnTheImportOnly) {
  ServerProcess server(data_.path(), {"--no-demo"});
  const auto r = Http(server).Get("/openapi.json");
  ASSERT_EQ(r->status, 200);
  const json doc = json::parse(r->body);
  const json& content = doc["paths"][kImport]["post"]["requestBody"]["content"];
  EXPECT_TRUE(content.contains("application/octet-stream")) << content.dump();
  ASSERT_TRUE(content.contains("multipart/form-data")) << content.dump();
  EXPECT_EQ(content["multipart/form-data"]["schema"]["properties"]["files"]["items"]["format"], "binary");
  int forms = 0;
  for (const auto& [path, methods] : doc["paths"].items())
    for (const auto& [method, op] : methods.items())
      if (op.contains("requestBody") && op["requestBody"]["content"].contains("multipart/form-data")) ++forms;
  EXPECT_EQ(forms, 1);
}

}  // namespace
}  // namespace armature::testing
