// The little of S3's XML answers the client reads: an error's Code and
// Message, and a ListObjectsV2 page (keys, sizes, continuation). Pure.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "armature/base/status.h"
#include "server/assets/bucket/object_store.h"

namespace armature::server {

struct ListPage {
  std::vector<ObjectEntry> entries;
  bool truncated = false;
  std::string next_token;
};

// The text of the first <tag>…</tag> in `xml`, entities decoded; "" if none.
std::string XmlText(std::string_view xml, std::string_view tag);

// INTERNAL when the page is not a ListBucketResult.
StatusOr<ListPage> ParseListPage(std::string_view xml);

}  // namespace armature::server
