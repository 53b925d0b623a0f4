// HTTP(S) GET for tests, through the curl command-line tool.
#pragma once

#include <string>
#include <vector>

namespace armature::testing {

struct HttpResponse {
  int status = 0;  // 0: no response (connection refused, TLS failure, …)
  std::string body;
  std::string error;  // curl's message when status is 0
};

// `headers` as "Name: value"; `ca_file` (PEM) to trust for https:// urls.
HttpResponse HttpGet(const std::string& url, const std::vector<std::string>& headers = {},
                     const std::string& ca_file = "");

}  // namespace armature::testing
