// Reading a request's headers the way every protocol of the gateway needs.
#pragma once

#include <string>
#include <vector>

namespace httplib {
struct Request;
}

namespace armature::server::gateway {

// The request's Content-Type without parameters, lower case, no spaces.
std::string MediaType(const httplib::Request& req);
// The comma-separated items of every value of header `name`, trimmed.
std::vector<std::string> HeaderItems(const httplib::Request& req, const char* name);

}  // namespace armature::server::gateway
