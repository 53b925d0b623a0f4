#include "http_get.h"

#include "server_process.h"

namespace armature::testing {

HttpResponse HttpGet(const std::string& url, const std::vector<std::string>& headers, const std::string& ca_file) {
  TempDir dir;
  const std::string body = (dir.path() / "body").string();
  std::string line = "curl -sS --max-time 20 -o " + ShellQuote(body) + " -w '%{http_code}'";
  for (const std::string& h : headers) line += " -H " + ShellQuote(h);
  if (!ca_file.empty()) line += " --cacert " + ShellQuote(ca_file);
  line += " " + ShellQuote(url);
  const CommandResult r = RunCommand(line);
  HttpResponse response;
  response.status = r.exit_code == 0 ? std::atoi(r.out.c_str()) : 0;
  response.body = ReadFile(body);
  response.error = r.err;
  return response;
}

}  // namespace armature::testing
