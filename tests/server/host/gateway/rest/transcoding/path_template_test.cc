// Path templates: variables, verbs and wildcards matched, malformed
// templates and paths refused.
#include <gtest/gtest.h>

#include "server/host/gateway/rest/transcoding/path_template.h"

namespace armature::server::gateway {
namespace {

PathBindings MatchOrDie(const std::string& tmpl, const std::string& path) {
  auto t = PathTemplate::Parse(tmpl);
  EXPECT_TRUE(t.ok()) << t.status().message();
  auto p = RequestPath::Parse(path);
  EXPECT_TRUE(p.ok()) << p.status().message();
  PathBindings b;
  EXPECT_TRUE(t->Match(*p, &b)) << tmpl << " vs " << path;
  return b;
}

bool Matches(const std::string& tmpl, const std::string& path) {
  PathBindings b;
  return PathTemplate::Parse(tmpl)->Match(*RequestPath::Parse(path), &b);
}

TEST(PathTemplate, VariablesVerbsAndWildcards) {
  EXPECT_EQ(MatchOrDie("/v1/clips/{clip}", "/v1/clips/walk"), (PathBindings{{"clip", "walk"}}));
  EXPECT_EQ(MatchOrDie("/v1/clips/{clip}:evaluate", "/v1/clips/walk:evaluate"), (PathBindings{{"clip", "walk"}}));
  // Segments are percent-decoded; a name may hold '/' or ':' when escaped or verb-less.
  EXPECT_EQ(MatchOrDie("/v1/clips/{clip}", "/v1/clips/a%2Fb%20c"), (PathBindings{{"clip", "a/b c"}}));
  EXPECT_EQ(MatchOrDie("/v1/clips/{clip}", "/v1/clips/a:b"), (PathBindings{{"clip", "a:b"}}));
  EXPECT_EQ(MatchOrDie("/v1/{name=assets/*}", "/v1/assets/x"), (PathBindings{{"name", "assets/x"}}));
  EXPECT_EQ(MatchOrDie("/v1/{name=files/**}:get", "/v1/files/a/b/c:get"), (PathBindings{{"name", "files/a/b/c"}}));
  EXPECT_EQ(MatchOrDie("/v1/{pose.name}/*", "/v1/p/q"), (PathBindings{{"pose.name", "p"}}));
  EXPECT_FALSE(Matches("/v1/clips/{clip}:evaluate", "/v1/clips/walk"));
  EXPECT_FALSE(Matches("/v1/clips/{clip}:evaluate", "/v1/clips/walk:stream"));
  EXPECT_FALSE(Matches("/v1/clips/{clip}", "/v1/clips/walk/extra"));
  EXPECT_FALSE(Matches("/v1/clips/{clip}", "/v1/clips/"));
  EXPECT_FALSE(Matches("/v1/clips", "/v1/clip"));
  EXPECT_EQ(PathTemplate::Parse("/v1/{name=assets/*}:x")->Simplified(), "/v1/{name}:x");
  EXPECT_GT(PathTemplate::Parse("/v1/clips/{clip}:stream")->specificity(),
            PathTemplate::Parse("/v1/clips/{clip}")->specificity());
}

TEST(PathTemplate, MalformedTemplatesAndPathsAreErrors) {
  for (const char* bad :
       {"v1/x", "/v1//x", "/v1/{x", "/v1/{x=**}/y", "/v1/{1x}", "/v1/{a.}", "/v1/x:", "/v1/{a={b}}"}) {
    auto t = PathTemplate::Parse(bad);
    EXPECT_FALSE(t.ok()) << bad;
    if (!t.ok()) EXPECT_NE(t.status().message().find("path template"), std::string::npos) << t.status().message();
  }
  EXPECT_FALSE(RequestPath::Parse("/v1/clips/%zz").ok());
  EXPECT_FALSE(RequestPath::Parse("/v1/clips/%4").ok());
}

}  // namespace
}  // namespace armature::server::gateway
