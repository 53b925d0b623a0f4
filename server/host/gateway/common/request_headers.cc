#include "server/host/gateway/common/request_headers.h"

#include <algorithm>
#include <cctype>

#include <httplib.h>

namespace armature::server::gateway {

std::string MediaType(const httplib::Request& req) {
  std::string type = req.get_header_value("Content-Type");
  type = type.substr(0, type.find(';'));
  type.erase(std::remove_if(type.begin(), type.end(), [](unsigned char c) { return std::isspace(c); }), type.end());
  std::transform(type.begin(), type.end(), type.begin(), [](unsigned char c) { return std::tolower(c); });
  return type;
}

std::vector<std::string> HeaderItems(const httplib::Request& req, const char* name) {
  std::vector<std::string> items;
  for (size_t i = 0; i < req.get_header_value_count(name); ++i) {
    const std::string value = req.get_header_value(name, i);
    size_t start = 0;
    while (start <= value.size()) {
      const size_t end = std::min(value.find(',', start), value.size());
      std::string item = value.substr(start, end - start);
      item.erase(0, item.find_first_not_of(" \t"));
      item.erase(item.find_last_not_of(" \t") + 1);
      if (!item.empty()) items.push_back(std::move(item));
      start = end + 1;
    }
  }
  return items;
}

}  // namespace armature::server::gateway
