#include "server/host/gateway/rest/json/json_writer.h"

#include <algorithm>
#include <charconv>
#include <vector>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/reflection.h>
#include <google/protobuf/stubs/strutil.h>

#include "server/host/gateway/rest/json/json_number.h"
#include "server/host/gateway/rest/json/json_string.h"

namespace armature::server::gateway {
namespace {

namespace pb = google::protobuf;
using Cpp = pb::FieldDescriptor::CppType;

class JsonWriter {
 public:
  JsonWriter(size_t max_bytes, std::string* out) : max_bytes_(max_bytes), out_(*out) {}

  // protobuf's printer fills a tree in declaration order, except that a set
  // scalar in a oneof (or a proto3 optional) has no place in it and comes
  // after the rest, in field-number order (the order of the wire).
  bool Message(const pb::Message& message) {
    const pb::Descriptor* type = message.GetDescriptor();
    const pb::Reflection* r = message.GetReflection();
    out_.push_back('{');
    bool first = true;
    std::vector<const pb::FieldDescriptor*> trailing;
    for (int i = 0; i < type->field_count(); ++i) {
      const pb::FieldDescriptor* field = type->field(i);
      if (!field->is_repeated() && HasPresence(*field) && !r->HasField(message, field)) continue;
      if (field->containing_oneof() != nullptr && field->cpp_type() != Cpp::CPPTYPE_MESSAGE) {
        trailing.push_back(field);
        continue;
      }
      if (!Member(message, *field, &first)) return false;
    }
    std::sort(trailing.begin(), trailing.end(), [](auto* a, auto* b) { return a->number() < b->number(); });
    for (const pb::FieldDescriptor* field : trailing)
      if (!Member(message, *field, &first)) return false;
    out_.push_back('}');
    return Fits();
  }

  // The field's value: its list, map or single value.
  bool Field(const pb::Message& message, const pb::FieldDescriptor& field) {
    if (field.is_map()) return Map(message, field);
    if (field.is_repeated()) return List(message, field);
    return Single(message, field);
  }

 private:
  bool Member(const pb::Message& message, const pb::FieldDescriptor& field, bool* first) {
    if (!*first) out_.push_back(',');
    *first = false;
    out_.push_back('"');
    out_.append(field.json_name());
    out_.append("\":");
    return Field(message, field);
  }

  static bool HasPresence(const pb::FieldDescriptor& field) {
    return field.cpp_type() == Cpp::CPPTYPE_MESSAGE || field.containing_oneof() != nullptr ||
           field.file()->syntax() != pb::FileDescriptor::SYNTAX_PROTO3;
  }

  bool Fits() const { return out_.size() <= max_bytes_; }

  template <class T, class Append>
  bool Elements(const pb::Message& message, const pb::FieldDescriptor& field, Append append) {
    const auto values = message.GetReflection()->GetRepeatedFieldRef<T>(message, &field);
    const int n = values.size();
    for (int i = 0; i < n; ++i) {
      if (i) out_.push_back(',');
      append(values.Get(i));
      if (!Fits()) return false;
    }
    return true;
  }

  bool List(const pb::Message& message, const pb::FieldDescriptor& field) {
    out_.push_back('[');
    bool ok = true;
    switch (field.cpp_type()) {
      case Cpp::CPPTYPE_FLOAT: ok = Elements<float>(message, field, [&](float v) { AppendJsonFloat(v, &out_); }); break;
      case Cpp::CPPTYPE_DOUBLE:
        ok = Elements<double>(message, field, [&](double v) { AppendJsonDouble(v, &out_); });
        break;
      case Cpp::CPPTYPE_INT32: ok = Elements<int32_t>(message, field, [&](int32_t v) { Number(v); }); break;
      case Cpp::CPPTYPE_UINT32: ok = Elements<uint32_t>(message, field, [&](uint32_t v) { Number(v); }); break;
      case Cpp::CPPTYPE_INT64: ok = Elements<int64_t>(message, field, [&](int64_t v) { Quoted(v); }); break;
      case Cpp::CPPTYPE_UINT64: ok = Elements<uint64_t>(message, field, [&](uint64_t v) { Quoted(v); }); break;
      case Cpp::CPPTYPE_BOOL: ok = Elements<bool>(message, field, [&](bool v) { Bool(v); }); break;
      case Cpp::CPPTYPE_ENUM: {
        const pb::Reflection* r = message.GetReflection();
        const int n = r->FieldSize(message, &field);
        for (int i = 0; i < n && ok; ++i) {
          if (i) out_.push_back(',');
          Enum(*field.enum_type(), r->GetRepeatedEnumValue(message, &field, i));
        }
        break;
      }
      case Cpp::CPPTYPE_STRING:
        ok = Elements<std::string>(message, field, [&](const std::string& v) { String(field, v); });
        break;
      case Cpp::CPPTYPE_MESSAGE: {
        const pb::Reflection* r = message.GetReflection();
        const int n = r->FieldSize(message, &field);
        for (int i = 0; i < n && ok; ++i) {
          if (i) out_.push_back(',');
          ok = Message(r->GetRepeatedMessage(message, &field, i));
        }
        break;
      }
    }
    out_.push_back(']');
    return ok && Fits();
  }

  // A map as an object; its keys as strings, in the map's own order (as protobuf's printer).
  bool Map(const pb::Message& message, const pb::FieldDescriptor& field) {
    const pb::Reflection* r = message.GetReflection();
    const pb::FieldDescriptor* key = field.message_type()->map_key();
    const pb::FieldDescriptor* value = field.message_type()->map_value();
    out_.push_back('{');
    const int n = r->FieldSize(message, &field);
    for (int i = 0; i < n; ++i) {
      const pb::Message& entry = r->GetRepeatedMessage(message, &field, i);
      if (i) out_.push_back(',');
      MapKey(entry, *key);
      out_.push_back(':');
      if (!Single(entry, *value)) return false;
    }
    out_.push_back('}');
    return Fits();
  }

  void MapKey(const pb::Message& entry, const pb::FieldDescriptor& key) {
    const pb::Reflection* r = entry.GetReflection();
    char buf[32];
    const auto text = [&](auto v) { return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr); };
    switch (key.cpp_type()) {
      case Cpp::CPPTYPE_STRING: return AppendJsonString(r->GetString(entry, &key), &out_);
      case Cpp::CPPTYPE_BOOL: return AppendJsonString(r->GetBool(entry, &key) ? "true" : "false", &out_);
      case Cpp::CPPTYPE_INT32: return AppendJsonString(text(r->GetInt32(entry, &key)), &out_);
      case Cpp::CPPTYPE_UINT32: return AppendJsonString(text(r->GetUInt32(entry, &key)), &out_);
      case Cpp::CPPTYPE_INT64: return AppendJsonString(text(r->GetInt64(entry, &key)), &out_);
      case Cpp::CPPTYPE_UINT64: return AppendJsonString(text(r->GetUInt64(entry, &key)), &out_);
      default: return AppendJsonString("", &out_);  // no other key types exist
    }
  }

  bool Single(const pb::Message& message, const pb::FieldDescriptor& field) {
    const pb::Reflection* r = message.GetReflection();
    switch (field.cpp_type()) {
      case Cpp::CPPTYPE_FLOAT: AppendJsonFloat(r->GetFloat(message, &field), &out_); break;
      case Cpp::CPPTYPE_DOUBLE: AppendJsonDouble(r->GetDouble(message, &field), &out_); break;
      case Cpp::CPPTYPE_INT32: Number(r->GetInt32(message, &field)); break;
      case Cpp::CPPTYPE_UINT32: Number(r->GetUInt32(message, &field)); break;
      case Cpp::CPPTYPE_INT64: Quoted(r->GetInt64(message, &field)); break;
      case Cpp::CPPTYPE_UINT64: Quoted(r->GetUInt64(message, &field)); break;
      case Cpp::CPPTYPE_BOOL: Bool(r->GetBool(message, &field)); break;
      case Cpp::CPPTYPE_ENUM: Enum(*field.enum_type(), r->GetEnumValue(message, &field)); break;
      case Cpp::CPPTYPE_STRING: {
        std::string scratch;
        String(field, r->GetStringReference(message, &field, &scratch));
        break;
      }
      case Cpp::CPPTYPE_MESSAGE: return Message(r->GetMessage(message, &field));
    }
    return Fits();
  }

  template <class T>
  void Number(T v) {
    char buf[24];
    out_.append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
  }
  template <class T>
  void Quoted(T v) {
    out_.push_back('"');
    Number(v);
    out_.push_back('"');
  }
  void Bool(bool v) { out_.append(v ? "true" : "false"); }
  // By name; a number the enum does not name stays a number.
  void Enum(const pb::EnumDescriptor& type, int value) {
    if (const pb::EnumValueDescriptor* named = type.FindValueByNumber(value))
      AppendJsonString(named->name(), &out_);
    else
      Number(value);
  }
  void String(const pb::FieldDescriptor& field, const std::string& v) {
    if (field.type() != pb::FieldDescriptor::TYPE_BYTES) return AppendJsonString(v, &out_);
    // Base64 with padding, written in place.
    const size_t at = out_.size();
    const int length = pb::CalculateBase64EscapedLen(static_cast<int>(v.size()), true);
    out_.resize(at + 1 + length);
    out_[at] = '"';
    pb::Base64Escape(reinterpret_cast<const unsigned char*>(v.data()), static_cast<int>(v.size()), &out_[at + 1],
                     length);
    out_.push_back('"');
  }

  size_t max_bytes_;
  std::string& out_;
};

}  // namespace

bool AppendMessageJson(const pb::Message& message, size_t max_bytes, std::string* out) {
  return JsonWriter(max_bytes, out).Message(message);
}

bool AppendFieldJson(const pb::Message& message, const pb::FieldDescriptor& field, size_t max_bytes, std::string* out) {
  return JsonWriter(max_bytes, out).Field(message, field);
}

}  // namespace armature::server::gateway
