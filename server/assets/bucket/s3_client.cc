#include "server/assets/bucket/s3_client.h"

#include <curl/curl.h>

#include <cstdlib>
#include <mutex>
#include <thread>

#include "server/assets/bucket/bucket_layout.h"
#include "server/assets/bucket/s3_xml.h"

namespace armature::server {
namespace {

size_t AppendBody(char* data, size_t size, size_t count, void* out) {
  static_cast<std::string*>(out)->append(data, size * count);
  return size * count;
}

void InitCurlOnce() {
  static std::once_flag once;
  std::call_once(once, [] { curl_global_init(CURL_GLOBAL_DEFAULT); });
}

struct CurlHandle {
  CURL* curl = curl_easy_init();
  curl_slist* headers = nullptr;
  ~CurlHandle() {
    curl_slist_free_all(headers);
    curl_easy_cleanup(curl);
  }
};

}  // namespace

std::string UriEncode(std::string_view text, bool keep_slash) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out;
  for (char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~' || (keep_slash && c == '/')) {
      out += ch;
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

S3Client::S3Client(StoreLocation location, AwsCredentials credentials, S3Timeouts timeouts)
    : location_(std::move(location)), credentials_(std::move(credentials)), timeouts_(timeouts) {
  InitCurlOnce();
}

StatusOr<S3Client::Reply> S3Client::Send(const std::string& method, const std::string& key, const std::string& query,
                                         std::string_view body) {
  // S3 answers "InternalError, please try again" (500) and SlowDown (503) now and then: a
  // few quick retries, as the AWS SDKs do. An unreachable endpoint is not retried here.
  constexpr int kAttempts = 3;
  for (int attempt = 1;; ++attempt) {
    auto reply = SendOnce(method, key, query, body);
    const bool transient = reply.ok() && (reply->http_status >= 500 || reply->http_status == 429);
    if (!transient || attempt == kAttempts) return reply;
    std::this_thread::sleep_for(std::chrono::milliseconds(50 << (2 * attempt)));
  }
}

StatusOr<S3Client::Reply> S3Client::SendOnce(const std::string& method, const std::string& key,
                                             const std::string& query, std::string_view body) {
  CurlHandle h;
  if (!h.curl) return Status::Internal("object store: curl_easy_init failed");
  std::string url = location_.Endpoint() + "/" + location_.bucket + "/" + UriEncode(key, true);
  if (!query.empty()) url += "?" + query;
  Reply reply;
  char error[CURL_ERROR_SIZE] = {};
  const std::string signer = "aws:amz:" + credentials_.region + ":s3";
  const std::string user = credentials_.access_key_id + ":" + credentials_.secret_access_key;
  // S3 wants the payload's hash in a header of its own; curl signs it with the rest.
  h.headers = curl_slist_append(h.headers, ("x-amz-content-sha256: " + Sha256Hex(body)).c_str());
  if (!credentials_.session_token.empty())
    h.headers = curl_slist_append(h.headers, ("x-amz-security-token: " + credentials_.session_token).c_str());
  h.headers = curl_slist_append(h.headers, "Content-Type: application/octet-stream");
  h.headers = curl_slist_append(h.headers, "Expect:");  // no 100-continue round trip
  curl_easy_setopt(h.curl, CURLOPT_URL, url.c_str());
  curl_easy_setopt(h.curl, CURLOPT_ERRORBUFFER, error);
  curl_easy_setopt(h.curl, CURLOPT_NOSIGNAL, 1L);
  curl_easy_setopt(h.curl, CURLOPT_CONNECTTIMEOUT_MS, static_cast<long>(timeouts_.connect.count()));
  curl_easy_setopt(h.curl, CURLOPT_TIMEOUT_MS, static_cast<long>(timeouts_.total.count()));
  curl_easy_setopt(h.curl, CURLOPT_AWS_SIGV4, signer.c_str());
  curl_easy_setopt(h.curl, CURLOPT_USERPWD, user.c_str());
  curl_easy_setopt(h.curl, CURLOPT_HTTPHEADER, h.headers);
  curl_easy_setopt(h.curl, CURLOPT_WRITEFUNCTION, AppendBody);
  curl_easy_setopt(h.curl, CURLOPT_WRITEDATA, &reply.body);
  if (const char* ca = std::getenv("AWS_CA_BUNDLE"); ca && *ca) curl_easy_setopt(h.curl, CURLOPT_CAINFO, ca);
  if (method == "PUT") {
    curl_easy_setopt(h.curl, CURLOPT_CUSTOMREQUEST, "PUT");
    curl_easy_setopt(h.curl, CURLOPT_POSTFIELDSIZE_LARGE, static_cast<curl_off_t>(body.size()));
    curl_easy_setopt(h.curl, CURLOPT_POSTFIELDS, body.data());
  } else if (method == "DELETE") {
    curl_easy_setopt(h.curl, CURLOPT_CUSTOMREQUEST, "DELETE");
  }
  const CURLcode rc = curl_easy_perform(h.curl);
  if (rc != CURLE_OK)
    return Status::Unavailable("object store " + Describe() +
                               " unreachable: " + (error[0] ? std::string(error) : curl_easy_strerror(rc)));
  curl_easy_getinfo(h.curl, CURLINFO_RESPONSE_CODE, &reply.http_status);
  return reply;
}

Status S3Client::ErrorOf(const std::string& what, const Reply& reply) const {
  const std::string code = XmlText(reply.body, "Code"), message = XmlText(reply.body, "Message");
  const std::string text = "object store " + Describe() + ": " + what + ": HTTP " + std::to_string(reply.http_status) +
                           (code.empty() ? "" : " " + code) + (message.empty() ? "" : " (" + message + ")");
  if (reply.http_status == 403 || reply.http_status == 401)
    return {StatusCode::kPermissionDenied, text + "; check the credentials (" + credentials_.source + ")"};
  if (code == "NoSuchBucket") return Status::FailedPrecondition(text);
  if (reply.http_status == 404) return Status::NotFound(text);
  if (reply.http_status >= 500 || reply.http_status == 429) return Status::Unavailable(text);
  return Status::Internal(text);
}

Status S3Client::Put(const std::string& key, std::string_view bytes) {
  ARMATURE_ASSIGN_OR_RETURN(Reply reply, Send("PUT", key, "", bytes));
  return reply.http_status / 100 == 2 ? Status::Ok() : ErrorOf("put " + key, reply);
}

StatusOr<std::string> S3Client::Get(const std::string& key) {
  ARMATURE_ASSIGN_OR_RETURN(Reply reply, Send("GET", key, "", ""));
  if (reply.http_status / 100 != 2) return ErrorOf("get " + key, reply);
  return std::move(reply.body);
}

Status S3Client::Delete(const std::string& key) {
  ARMATURE_ASSIGN_OR_RETURN(Reply reply, Send("DELETE", key, "", ""));
  return reply.http_status / 100 == 2 || reply.http_status == 404 ? Status::Ok() : ErrorOf("delete " + key, reply);
}

StatusOr<std::vector<ObjectEntry>> S3Client::List(const std::string& prefix) {
  std::vector<ObjectEntry> entries;
  std::string token;
  do {
    // SigV4's canonical query: parameters sorted by name, values encoded.
    std::string query = token.empty() ? "" : "continuation-token=" + UriEncode(token, false) + "&";
    query += "list-type=2&max-keys=" + std::to_string(page_size_) + "&prefix=" + UriEncode(prefix, false);
    ARMATURE_ASSIGN_OR_RETURN(Reply reply, Send("GET", "", query, ""));
    if (reply.http_status / 100 != 2) return ErrorOf("list " + prefix, reply);
    ARMATURE_ASSIGN_OR_RETURN(ListPage page, ParseListPage(reply.body));
    for (auto& entry : page.entries) entries.push_back(std::move(entry));
    token = page.truncated ? page.next_token : "";
    if (page.truncated && token.empty())
      return Status::Internal("object store " + Describe() + ": a truncated listing without a continuation token");
  } while (!token.empty());
  return entries;
}

}  // namespace armature::server
