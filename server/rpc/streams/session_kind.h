// The kinds of long-lived session, each counted apart by SessionAdmission
// (armature_sessions_active{kind}); a session's logic names its own kind.
#pragma once

namespace armature::server {

enum class SessionKind { kIk, kDeform, kPlayback, kCrowd };
inline constexpr int kSessionKindCount = 4;

}  // namespace armature::server
