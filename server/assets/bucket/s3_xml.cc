#include "server/assets/bucket/s3_xml.h"

#include <charconv>

namespace armature::server {
namespace {

std::string DecodeEntities(std::string_view text) {
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '&') {
      out += text[i];
      continue;
    }
    const size_t semi = text.find(';', i);
    const std::string_view entity = text.substr(i + 1, semi == std::string_view::npos ? 0 : semi - i - 1);
    char c = 0;
    if (entity == "amp") c = '&';
    if (entity == "lt") c = '<';
    if (entity == "gt") c = '>';
    if (entity == "quot") c = '"';
    if (entity == "apos") c = '\'';
    if (entity.starts_with("#")) {
      int code = 0;
      const bool hex = entity.size() > 1 && (entity[1] == 'x' || entity[1] == 'X');
      const std::string_view digits = entity.substr(hex ? 2 : 1);
      std::from_chars(digits.data(), digits.data() + digits.size(), code, hex ? 16 : 10);
      if (code > 0 && code < 128) c = static_cast<char>(code);
    }
    if (c == 0) {
      out += '&';
      continue;
    }
    out += c;
    i = semi;
  }
  return out;
}

// The element `tag`'s raw text (entities kept) from `from` on; `from` moves
// past it. False when none.
bool NextElement(std::string_view xml, std::string_view tag, size_t& from, std::string_view& text) {
  // Appended piece by piece: GCC 12's -Wrestrict misreads "<" + std::string(...) here.
  std::string open = "<", close = "</";
  open.append(tag).push_back('>');
  close.append(tag).push_back('>');
  const size_t begin = xml.find(open, from);
  if (begin == std::string_view::npos) return false;
  const size_t end = xml.find(close, begin + open.size());
  if (end == std::string_view::npos) return false;
  text = xml.substr(begin + open.size(), end - begin - open.size());
  from = end + close.size();
  return true;
}

}  // namespace

std::string XmlText(std::string_view xml, std::string_view tag) {
  size_t from = 0;
  std::string_view text;
  return NextElement(xml, tag, from, text) ? DecodeEntities(text) : "";
}

StatusOr<ListPage> ParseListPage(std::string_view xml) {
  if (xml.find("<ListBucketResult") == std::string_view::npos)
    return Status::Internal("object store: a listing that is not a ListBucketResult");
  ListPage page;
  size_t from = 0;
  std::string_view contents;
  while (NextElement(xml, "Contents", from, contents)) {
    ObjectEntry entry;
    const std::string size = XmlText(contents, "Size");
    std::from_chars(size.data(), size.data() + size.size(), entry.size);
    entry.key = XmlText(contents, "Key");
    page.entries.push_back(std::move(entry));
  }
  page.truncated = XmlText(xml, "IsTruncated") == "true";
  page.next_token = XmlText(xml, "NextContinuationToken");
  return page;
}

}  // namespace armature::server
