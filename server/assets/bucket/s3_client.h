// An ObjectStore over S3's REST API with libcurl: path-style URLs
// (ENDPOINT/BUCKET/KEY), Signature V4 by curl (CURLOPT_AWS_SIGV4), the
// payload's SHA-256 sent and signed, a session token when there is one.
// Every request has a connect and a total timeout; HTTPS verifies the
// server against the system's CAs, or AWS_CA_BUNDLE when set.
#pragma once

#include <chrono>
#include <memory>
#include <string>

#include "server/assets/bucket/aws_credentials.h"
#include "server/assets/bucket/object_store.h"
#include "server/assets/bucket/store_url.h"

namespace armature::server {

struct S3Timeouts {
  std::chrono::milliseconds connect{2000};
  std::chrono::milliseconds total{30000};  // a whole request, body included
};

class S3Client : public ObjectStore {
 public:
  S3Client(StoreLocation location, AwsCredentials credentials, S3Timeouts timeouts = {});

  Status Put(const std::string& key, std::string_view bytes) override;
  StatusOr<std::string> Get(const std::string& key) override;
  StatusOr<std::vector<ObjectEntry>> List(const std::string& prefix) override;
  Status Delete(const std::string& key) override;
  std::string Describe() const override { return location_.Endpoint() + "/" + location_.bucket; }

  // Keys per ListObjectsV2 page (S3's most is 1000); smaller in tests of paging.
  void set_page_size(int keys) { page_size_ = keys; }

 private:
  struct Reply {
    long http_status = 0;
    std::string body;
  };
  // One signed request, retried on 5xx; `query` is already canonical (sorted, encoded).
  StatusOr<Reply> Send(const std::string& method, const std::string& key, const std::string& query,
                       std::string_view body);
  StatusOr<Reply> SendOnce(const std::string& method, const std::string& key, const std::string& query,
                           std::string_view body);
  // The Status of a reply that is not 2xx, with S3's error code and message.
  Status ErrorOf(const std::string& what, const Reply& reply) const;

  StoreLocation location_;
  AwsCredentials credentials_;
  S3Timeouts timeouts_;
  int page_size_ = 1000;
};

// A key or query value as SigV4 encodes it: everything but A-Z a-z 0-9 - _ . ~
// percent-encoded, '/' too unless `keep_slash`.
std::string UriEncode(std::string_view text, bool keep_slash);

}  // namespace armature::server
