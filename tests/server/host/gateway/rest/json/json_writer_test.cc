// The gateway's JSON writer against protobuf's MessageToJsonString with the
// options the gateway used (lowerCamelCase, primitive fields always printed):
// byte for byte, over every response type the API returns, filled at random
// (NaN and infinities, -0, subnormals, empty lists, unknown enum numbers,
// oneofs, 64-bit integers, bytes, escapes and broken UTF-8), and over a type
// made at run time with what the API does not use yet (maps, proto3
// optional, every scalar type). Numbers alone against SimpleFtoa/SimpleDtoa.
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <set>

#include <google/protobuf/descriptor.pb.h>
#include <google/protobuf/dynamic_message.h>
#include <google/protobuf/stubs/logging.h>
#include <google/protobuf/stubs/strutil.h>
#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

#include "armature/v1/poses.pb.h"
#include "server/host/gateway/rest/transcoding/http_rule.h"
#include "server/host/gateway/rest/json/json_number.h"
#include "server/host/gateway/rest/json/json_writer.h"
#include "server/host/gateway/rest/json/json_codec.h"
#include "server/host/gateway/rest/transcoding/transcoder.h"

namespace armature::server::gateway {
namespace {

namespace pb = google::protobuf;
using Cpp = pb::FieldDescriptor::CppType;

std::string ProtobufJson(const pb::Message& message) {
  pb::util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;
  options.preserve_proto_field_names = false;
  std::string out;
  const auto st = pb::util::MessageToJsonString(message, &out, options);
  EXPECT_TRUE(st.ok()) << st.ToString();
  return out;
}

// Fills a message with values picked from the awkward ones.
class Filler {
 public:
  explicit Filler(uint64_t seed) : rng_(seed) {}

  void Fill(pb::Message* m, int depth) {
    const pb::Descriptor* type = m->GetDescriptor();
    const pb::Reflection* r = m->GetReflection();
    for (int i = 0; i < type->field_count(); ++i) {
      const pb::FieldDescriptor* f = type->field(i);
      if (Pick(3) == 0) continue;  // left unset
      if (f->cpp_type() == Cpp::CPPTYPE_MESSAGE && depth >= 3) continue;
      if (f->is_repeated()) {
        const int n = static_cast<int>(Pick(4));
        for (int k = 0; k < n; ++k) Add(m, r, f, depth);
      } else {
        Set(m, r, f, depth);
      }
    }
  }

 private:
  uint64_t Pick(uint64_t n) { return rng_() % n; }

  float Float() {
    static const float kSpecial[] = {0.f,
                                     -0.f,
                                     1.f,
                                     -1.f,
                                     0.1f,
                                     1.f / 3,
                                     1e-5f,
                                     1e20f,
                                     123456.789f,
                                     0.70710677f,
                                     std::numeric_limits<float>::quiet_NaN(),
                                     std::numeric_limits<float>::infinity(),
                                     -std::numeric_limits<float>::infinity(),
                                     1e-40f,
                                     std::numeric_limits<float>::max(),
                                     std::numeric_limits<float>::min(),
                                     1e6f,
                                     999999.5f,
                                     100000.f,
                                     0.0001f,
                                     0.00001f};
    if (Pick(2)) return kSpecial[Pick(std::size(kSpecial))];
    const uint32_t bits = static_cast<uint32_t>(rng_());
    float f;
    std::memcpy(&f, &bits, 4);
    return Pick(2) ? f : std::uniform_real_distribution<float>(-2, 2)(rng_);
  }
  double Double() {
    static const double kSpecial[] = {0.,
                                      -0.,
                                      1. / 30,
                                      0.1,
                                      1e15,
                                      1e16,
                                      1e-300,
                                      4.9e-324,
                                      1e300,
                                      std::numeric_limits<double>::quiet_NaN(),
                                      -std::numeric_limits<double>::infinity(),
                                      123456789012345678.0};
    if (Pick(2)) return kSpecial[Pick(std::size(kSpecial))];
    const uint64_t bits = rng_();
    double d;
    std::memcpy(&d, &bits, 8);
    return Pick(2) ? d : std::uniform_real_distribution<double>(-100, 100)(rng_);
  }
  std::string Text() {
    static const char* kSpecial[] = {"",
                                     "walk",
                                     "a\"b\\c/d",
                                     "<script>&",
                                     "tab\tnew\nline\r\b\f",
                                     "\x01\x1f\x7f",
                                     "caf\xc3\xa9 \xe6\x97\xa5\xe6\x9c\xac",
                                     "\xff bad",
                                     "cut \xc3",
                                     "\xc3(x",
                                     "\xed\xa0\x80 surrogate",
                                     "\xe2\x80\xa8 sep \xc2\x85 \xc2\xad \xef\xbb\xbf",
                                     "\xf0\x9d\x85\xb3 music \xf3\xa0\x80\x81 tag",
                                     "\xc0\x80 overlong \xc1\x81",
                                     "\xf4\x90\x80\x80 past",
                                     "\xf0\x9f\x98\x80 emoji",
                                     "\xd8\x80 \xe2\x81\xaa"};
    return kSpecial[Pick(std::size(kSpecial))];
  }
  std::string Bytes() {
    std::string b(Pick(7), '\0');
    for (char& c : b) c = static_cast<char>(rng_());
    return b;
  }
  int Enum(const pb::EnumDescriptor& e) {
    if (Pick(5) == 0) return 77;  // a number the enum does not name
    return e.value(static_cast<int>(Pick(e.value_count())))->number();
  }
  int64_t Int64() {
    static const int64_t kSpecial[] = {
        0, -1, 1, std::numeric_limits<int64_t>::min(), std::numeric_limits<int64_t>::max(), 9007199254740993};
    return kSpecial[Pick(std::size(kSpecial))];
  }

  void Set(pb::Message* m, const pb::Reflection* r, const pb::FieldDescriptor* f, int depth) {
    switch (f->cpp_type()) {
      case Cpp::CPPTYPE_FLOAT: return r->SetFloat(m, f, Float());
      case Cpp::CPPTYPE_DOUBLE: return r->SetDouble(m, f, Double());
      case Cpp::CPPTYPE_INT32: return r->SetInt32(m, f, static_cast<int32_t>(Int64()));
      case Cpp::CPPTYPE_UINT32: return r->SetUInt32(m, f, static_cast<uint32_t>(Int64()));
      case Cpp::CPPTYPE_INT64: return r->SetInt64(m, f, Int64());
      case Cpp::CPPTYPE_UINT64: return r->SetUInt64(m, f, static_cast<uint64_t>(Int64()));
      case Cpp::CPPTYPE_BOOL: return r->SetBool(m, f, Pick(2));
      case Cpp::CPPTYPE_ENUM: return r->SetEnumValue(m, f, Enum(*f->enum_type()));
      case Cpp::CPPTYPE_STRING:
        return r->SetString(m, f, f->type() == pb::FieldDescriptor::TYPE_BYTES ? Bytes() : Text());
      case Cpp::CPPTYPE_MESSAGE: return Fill(r->MutableMessage(m, f), depth + 1);
    }
  }
  void Add(pb::Message* m, const pb::Reflection* r, const pb::FieldDescriptor* f, int depth) {
    switch (f->cpp_type()) {
      case Cpp::CPPTYPE_FLOAT: return r->AddFloat(m, f, Float());
      case Cpp::CPPTYPE_DOUBLE: return r->AddDouble(m, f, Double());
      case Cpp::CPPTYPE_INT32: return r->AddInt32(m, f, static_cast<int32_t>(Int64()));
      case Cpp::CPPTYPE_UINT32: return r->AddUInt32(m, f, static_cast<uint32_t>(Int64()));
      case Cpp::CPPTYPE_INT64: return r->AddInt64(m, f, Int64());
      case Cpp::CPPTYPE_UINT64: return r->AddUInt64(m, f, static_cast<uint64_t>(Int64()));
      case Cpp::CPPTYPE_BOOL: return r->AddBool(m, f, Pick(2));
      case Cpp::CPPTYPE_ENUM: return r->AddEnumValue(m, f, Enum(*f->enum_type()));
      case Cpp::CPPTYPE_STRING:
        return r->AddString(m, f, f->type() == pb::FieldDescriptor::TYPE_BYTES ? Bytes() : Text());
      case Cpp::CPPTYPE_MESSAGE: return Fill(r->AddMessage(m, f), depth + 1);
    }
  }

  std::mt19937_64 rng_;
};

void ExpectSameJsonAsProtobuf(const pb::Message& prototype, int rounds) {
  const pb::LogSilencer quiet;  // protobuf logs each string that is not UTF-8
  for (int seed = 0; seed < rounds; ++seed) {
    std::unique_ptr<pb::Message> m(prototype.New());
    if (seed > 0) Filler(seed).Fill(m.get(), 0);  // round 0: the empty message
    const std::string want = ProtobufJson(*m);
    const std::string got = MessageToJson(*m);
    ASSERT_EQ(got, want) << prototype.GetTypeName() << ", seed " << seed << ": " << m->ShortDebugString();
  }
}

TEST(JsonWriter, EveryResponseTypeOfTheApiIsWrittenAsProtobufWritesIt) {
  std::set<const pb::Descriptor*> types;
  for (const pb::ServiceDescriptor* service : GeneratedServicesIn("armature.v1"))
    for (int i = 0; i < service->method_count(); ++i) types.insert(service->method(i)->output_type());
  ASSERT_GE(types.size(), 20u);
  for (const pb::Descriptor* type : types)
    ExpectSameJsonAsProtobuf(*pb::MessageFactory::generated_factory()->GetPrototype(type), 200);
}

// A proto3 type with maps, proto3 optional and every scalar, built at run time.
const pb::Descriptor* EverythingType(pb::DescriptorPool* pool) {
  pb::FileDescriptorProto file;
  file.set_name("everything.proto");
  file.set_package("jsontest");
  file.set_syntax("proto3");
  auto* color = file.add_enum_type();
  color->set_name("Color");
  for (auto [name, number] : {std::pair{"COLOR_UNSPECIFIED", 0}, {"RED", 1}, {"GREEN", 5}}) {
    auto* v = color->add_value();
    v->set_name(name);
    v->set_number(number);
  }
  auto* sub = file.add_message_type();
  sub->set_name("Sub");
  auto* sub_field = sub->add_field();
  sub_field->set_name("value_x");
  sub_field->set_number(1);
  sub_field->set_type(pb::FieldDescriptorProto::TYPE_FLOAT);
  sub_field->set_label(pb::FieldDescriptorProto::LABEL_OPTIONAL);

  auto* m = file.add_message_type();
  m->set_name("Everything");
  int number = 1;
  auto add = [&](const std::string& name, pb::FieldDescriptorProto::Type type, bool repeated,
                 const std::string& type_name = "") {
    auto* f = m->add_field();
    f->set_name(name);
    f->set_number(number++);
    f->set_type(type);
    f->set_label(repeated ? pb::FieldDescriptorProto::LABEL_REPEATED : pb::FieldDescriptorProto::LABEL_OPTIONAL);
    if (!type_name.empty()) f->set_type_name(type_name);
    return f;
  };
  using T = pb::FieldDescriptorProto;
  const std::pair<const char*, T::Type> scalars[] = {
      {"f_double", T::TYPE_DOUBLE},     {"f_float", T::TYPE_FLOAT},   {"f_int64", T::TYPE_INT64},
      {"f_uint64", T::TYPE_UINT64},     {"f_int32", T::TYPE_INT32},   {"f_fixed64", T::TYPE_FIXED64},
      {"f_fixed32", T::TYPE_FIXED32},   {"f_bool", T::TYPE_BOOL},     {"f_string", T::TYPE_STRING},
      {"f_bytes", T::TYPE_BYTES},       {"f_uint32", T::TYPE_UINT32}, {"f_sfixed32", T::TYPE_SFIXED32},
      {"f_sfixed64", T::TYPE_SFIXED64}, {"f_sint32", T::TYPE_SINT32}, {"f_sint64", T::TYPE_SINT64}};
  for (const auto& [name, type] : scalars) {
    add(name, type, false);
    add(std::string("r") + name, type, true);
  }
  add("color", T::TYPE_ENUM, false, ".jsontest.Color");
  add("colors", T::TYPE_ENUM, true, ".jsontest.Color");
  add("sub", T::TYPE_MESSAGE, false, ".jsontest.Sub");
  add("subs", T::TYPE_MESSAGE, true, ".jsontest.Sub");
  // Oneof members and a proto3 optional (its synthetic oneof comes last).
  m->add_oneof_decl()->set_name("choice");
  add("choice_int", T::TYPE_INT32, false)->set_oneof_index(0);
  add("choice_sub", T::TYPE_MESSAGE, false, ".jsontest.Sub")->set_oneof_index(0);
  m->add_oneof_decl()->set_name("_maybe");
  auto* maybe = add("maybe", T::TYPE_DOUBLE, false);
  maybe->set_oneof_index(1);
  maybe->set_proto3_optional(true);
  // Maps: entry types nested in the message, in the order protoc writes them.
  const std::tuple<const char*, T::Type, T::Type, const char*> maps[] = {
      {"by_name", T::TYPE_STRING, T::TYPE_INT32, ""},
      {"by_id", T::TYPE_INT64, T::TYPE_MESSAGE, ".jsontest.Sub"},
      {"by_flag", T::TYPE_BOOL, T::TYPE_STRING, ""},
      {"by_number", T::TYPE_UINT32, T::TYPE_FLOAT, ""}};
  for (const auto& [name, key_type, value_type, value_type_name] : maps) {
    std::string entry_name = std::string(name) + "_entry";
    entry_name[0] = static_cast<char>(std::toupper(entry_name[0]));
    for (size_t i = 0; i < entry_name.size(); ++i)
      if (entry_name[i] == '_') entry_name.erase(i, 1), entry_name[i] = static_cast<char>(std::toupper(entry_name[i]));
    auto* entry = m->add_nested_type();
    entry->set_name(entry_name);
    entry->mutable_options()->set_map_entry(true);
    auto* key = entry->add_field();
    key->set_name("key");
    key->set_number(1);
    key->set_type(key_type);
    key->set_label(T::LABEL_OPTIONAL);
    auto* value = entry->add_field();
    value->set_name("value");
    value->set_number(2);
    value->set_type(value_type);
    value->set_label(T::LABEL_OPTIONAL);
    if (*value_type_name) value->set_type_name(value_type_name);
    add(name, T::TYPE_MESSAGE, true, ".jsontest.Everything." + entry_name);
  }
  const pb::FileDescriptor* built = pool->BuildFile(file);
  return built ? built->FindMessageTypeByName("Everything") : nullptr;
}

TEST(JsonWriter, MapsOptionalsAndEveryScalarTypeAreWrittenAsProtobufWritesThem) {
  pb::DescriptorPool pool;
  const pb::Descriptor* type = EverythingType(&pool);
  ASSERT_NE(type, nullptr);
  pb::DynamicMessageFactory factory(&pool);
  ExpectSameJsonAsProtobuf(*factory.GetPrototype(type), 500);
}

TEST(JsonWriter, StopsOnceTheTextPassesTheBound) {
  v1::EvaluateClipResponse response;
  response.set_clip("walk");
  for (int i = 0; i < 1000; ++i) response.add_times(i / 30.0);
  const std::string whole = MessageToJson(response);
  std::string cut;
  EXPECT_FALSE(MessageToJson(response, 1000, &cut));
  EXPECT_GT(cut.size(), 1000u);
  EXPECT_LT(cut.size(), 1100u) << "the writer stops within an element of the bound";
  std::string all;
  EXPECT_TRUE(MessageToJson(response, whole.size(), &all));
  EXPECT_EQ(all, whole);
}

TEST(JsonWriter, TranscodeResponseRefusesJsonOverTheBoundNamingTheBinaryEncoding) {
  const pb::MethodDescriptor* method =
      v1::EvaluateClipRequest::descriptor()->file()->FindServiceByName("PoseService")->FindMethodByName("EvaluateClip");
  auto bindings = BindingsOf(method);
  ASSERT_TRUE(bindings.ok() && !bindings->empty());
  v1::EvaluateClipResponse response;
  for (int i = 0; i < 100000; ++i) response.add_times(i / 30.0);
  const std::string serialized = response.SerializeAsString();
  HttpBody body;
  const grpc::Status refused =
      TranscodeResponse(bindings->front(), v1::EvaluateClipResponse::default_instance(), serialized, 1 << 20, &body);
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_EQ(refused.error_message(),
            "the answer as JSON passes the message limit of 1.0 MiB (--max-message-mb); ask for less, or for its "
            "binary encoding (0.8 MiB): header Accept: application/x-protobuf, or call over gRPC");
  EXPECT_TRUE(body.content.empty());
  const grpc::Status ok =
      TranscodeResponse(bindings->front(), v1::EvaluateClipResponse::default_instance(), serialized, 8 << 20, &body);
  EXPECT_TRUE(ok.ok()) << ok.error_message();
  EXPECT_EQ(body.content, ProtobufJson(response));
}

TEST(JsonNumber, FloatsAndDoublesAreProtobufsSimpleFtoaAndSimpleDtoa) {
  std::mt19937_64 rng(7);
  int differing = 0;
  auto check_float = [&](float f) {
    if (!std::isfinite(f)) return;
    std::string got;
    AppendJsonFloat(f, &got);
    if (got != pb::SimpleFtoa(f) && differing++ < 5) ADD_FAILURE() << got << " vs " << pb::SimpleFtoa(f);
  };
  auto check_double = [&](double d) {
    if (!std::isfinite(d)) return;
    std::string got;
    AppendJsonDouble(d, &got);
    if (got != pb::SimpleDtoa(d) && differing++ < 5) ADD_FAILURE() << got << " vs " << pb::SimpleDtoa(d);
  };
  for (int i = 0; i < 300000; ++i) {
    const uint64_t bits = rng();
    float f;
    double d;
    std::memcpy(&f, &bits, 4);
    std::memcpy(&d, &bits, 8);
    check_float(f);
    check_double(d);
    check_float(std::uniform_real_distribution<float>(-2, 2)(rng));
  }
  // Ties and carries at 6 and 9 digits, powers of two and ten, integers, subnormals.
  for (int i = 0; i < 20000; ++i) {
    check_float(static_cast<float>(i));
    check_float(i / 1000.f);
    check_float(std::ldexp(1.f, i % 280 - 150));
    check_float(std::nextafter(std::pow(10.f, static_cast<float>(i % 76 - 38)), 0.f));
    check_double(i / 30.0);
    check_double(std::ldexp(1.0, i % 2100 - 1075));
    check_double(std::nextafter(std::pow(10.0, i % 600 - 300), 0.0));
  }
  EXPECT_EQ(differing, 0);
  std::string text;
  AppendJsonFloat(std::numeric_limits<float>::quiet_NaN(), &text);
  AppendJsonDouble(-std::numeric_limits<double>::infinity(), &text);
  EXPECT_EQ(text, "\"NaN\"\"-Infinity\"");
}

}  // namespace
}  // namespace armature::server::gateway
