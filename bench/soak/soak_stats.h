// armature-soak's tally: per method the calls, refusals by design, errors by
// status and the latencies, printed as one table at the end.
#pragma once

#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <grpcpp/grpcpp.h>

namespace armature::soak {

struct MethodStats {
  std::vector<double> latencies_ms;
  int refused = 0;                    // IsExpectedRefusal
  std::map<std::string, int> errors;  // status code name → count
  std::string first_error;
};

// A refusal by an admission limit the soak may run into by design (50
// clients on one address hold more sessions than --max-sessions-per-client
// allows, and import more at once than --max-concurrent-uploads): counted,
// but not an error.
bool IsExpectedRefusal(const grpc::Status& st);

class Stats {
 public:
  void Record(const std::string& method, double ms, const grpc::Status& st);
  // Prints the table; returns the number of errors.
  int Report();

 private:
  std::mutex mu_;
  std::map<std::string, MethodStats> methods_;
};

}  // namespace armature::soak
