// One admitted place (a session, a stream): gives it back when destroyed or
// Release()d, so a reactor cannot leak one. Move-only.
#pragma once

#include <functional>
#include <utility>

namespace armature::server {

class AdmissionTicket {
 public:
  AdmissionTicket() = default;
  explicit AdmissionTicket(std::function<void()> release) : release_(std::move(release)) {}
  AdmissionTicket(AdmissionTicket&& other) noexcept : release_(std::exchange(other.release_, nullptr)) {}
  AdmissionTicket& operator=(AdmissionTicket&& other) noexcept {
    if (this != &other) {
      Release();
      release_ = std::exchange(other.release_, nullptr);
    }
    return *this;
  }
  AdmissionTicket(const AdmissionTicket&) = delete;
  AdmissionTicket& operator=(const AdmissionTicket&) = delete;
  ~AdmissionTicket() { Release(); }

  void Release() {  // idempotent
    if (auto release = std::exchange(release_, nullptr)) release();
  }

 private:
  std::function<void()> release_;
};

}  // namespace armature::server
