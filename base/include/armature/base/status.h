// Status and StatusOr: how every engine and server factory reports failure.
// The engine knows nothing of gRPC; server/rpc/grpc_status.cc is the single place
// that maps a StatusCode onto a grpc::StatusCode.
#pragma once

#include <cassert>
#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace armature {

enum class StatusCode {
  kOk,
  kInvalidArgument,
  kNotFound,
  kAlreadyExists,
  kResourceExhausted,
  kFailedPrecondition,
  kOutOfRange,
  kDeadlineExceeded,
  kCancelled,
  kUnavailable,
  kUnauthenticated,
  kPermissionDenied,
  kUnimplemented,
  kInternal,
  kAborted,  // a read-modify-write lost a race; the caller may try again
};

class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}

  static Status Ok() { return {}; }
  static Status InvalidArgument(std::string m) { return {StatusCode::kInvalidArgument, std::move(m)}; }
  static Status NotFound(std::string m) { return {StatusCode::kNotFound, std::move(m)}; }
  static Status AlreadyExists(std::string m) { return {StatusCode::kAlreadyExists, std::move(m)}; }
  static Status ResourceExhausted(std::string m) { return {StatusCode::kResourceExhausted, std::move(m)}; }
  static Status FailedPrecondition(std::string m) { return {StatusCode::kFailedPrecondition, std::move(m)}; }
  static Status DeadlineExceeded(std::string m) { return {StatusCode::kDeadlineExceeded, std::move(m)}; }
  static Status Cancelled(std::string m) { return {StatusCode::kCancelled, std::move(m)}; }
  static Status Unavailable(std::string m) { return {StatusCode::kUnavailable, std::move(m)}; }
  static Status Internal(std::string m) { return {StatusCode::kInternal, std::move(m)}; }
  static Status Aborted(std::string m) { return {StatusCode::kAborted, std::move(m)}; }

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }

  // Prefixes the message with context, e.g. "mesh 'body': " + message.
  Status WithContext(const std::string& prefix) const { return ok() ? *this : Status(code_, prefix + message_); }

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

// A value or the Status explaining why there is none.
template <class T>
class [[nodiscard]] StatusOr {
 public:
  StatusOr(T value) : v_(std::move(value)) {}                                              // NOLINT: implicit by design
  StatusOr(Status status) : v_(std::move(status)) { assert(!std::get<Status>(v_).ok()); }  // NOLINT

  bool ok() const { return std::holds_alternative<T>(v_); }
  Status status() const { return ok() ? Status::Ok() : std::get<Status>(v_); }

  T& value() & { return std::get<T>(v_); }
  const T& value() const& { return std::get<T>(v_); }
  T&& value() && { return std::get<T>(std::move(v_)); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }

 private:
  std::variant<T, Status> v_;
};

}  // namespace armature

// Returns early from the enclosing function when `expr` is not ok.
#define ARMATURE_RETURN_IF_ERROR(expr)           \
  do {                                           \
    ::armature::Status _armature_st = (expr);    \
    if (!_armature_st.ok()) return _armature_st; \
  } while (0)

#define ARMATURE_STATUS_CONCAT_INNER(a, b) a##b
#define ARMATURE_STATUS_CONCAT(a, b) ARMATURE_STATUS_CONCAT_INNER(a, b)

// `ARMATURE_ASSIGN_OR_RETURN(auto x, MakeX());` declares x from a StatusOr's value, or returns
// its Status from the enclosing function (which returns Status or any StatusOr).
#define ARMATURE_ASSIGN_OR_RETURN(lhs, expr) \
  ARMATURE_ASSIGN_OR_RETURN_IMPL(ARMATURE_STATUS_CONCAT(_armature_so_, __LINE__), lhs, expr)
#define ARMATURE_ASSIGN_OR_RETURN_IMPL(tmp, lhs, expr) \
  auto tmp = (expr);                                   \
  if (!tmp.ok()) return tmp.status();                  \
  lhs = std::move(tmp).value()
