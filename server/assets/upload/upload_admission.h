// Admission of uploads: each ImportAsset call holds what it received until it
// is imported, so at most --max-concurrent-uploads are received at once (over
// gRPC, and REST and gRPC-Web, which call it); one more is RESOURCE_EXHAUSTED
// naming the flag, answered before its data is read.
#pragma once

#include <atomic>

#include "armature/base/status.h"
#include "server/rpc/streams/admission_ticket.h"

namespace armature::server {

class UploadAdmission {
 public:
  explicit UploadAdmission(int max_uploads) : max_(max_uploads) {}
  UploadAdmission(const UploadAdmission&) = delete;
  UploadAdmission& operator=(const UploadAdmission&) = delete;

  // A place for one upload until the ticket goes. The admission must outlive its tickets.
  StatusOr<AdmissionTicket> Admit() {
    int open = open_.load();
    do {
      if (open >= max_)
        return Status::ResourceExhausted("too many uploads at once: " + std::to_string(open) +
                                         " are being received, the limit is " + std::to_string(max_) +
                                         " (--max-concurrent-uploads); try again when one has finished");
    } while (!open_.compare_exchange_weak(open, open + 1));
    return AdmissionTicket([this] { --open_; });
  }

 private:
  const int max_;
  std::atomic<int> open_{0};
};

}  // namespace armature::server
