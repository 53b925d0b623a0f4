// Which clip the Retarget panel offers first for a character: one on another
// skeleton (the character's own clips, and clips already retargeted onto it,
// would change nothing) whose joints read as a body RetargetClip can map:
// hips, a head, two hands and two feet, by the names exporters use.
const PARTS = [
  [/hips|pelvis/i, 1],
  [/head/i, 1],
  [/hand|wrist/i, 2],
  [/foot|ankle/i, 2],
];

// True when the joint names hold each part (hands and feet twice). Fingers
// ("LeftHandIndex1") count once per side at most: only names ending in the part count.
export function looksLikeABody(names) {
  return PARTS.every(([part, count]) => {
    const ends = new RegExp(`(${part.source})(\\b|_|\\.)?(l|r|left|right)?$`, 'i');
    return names.filter((n) => ends.test(n.replace(/^.*[:|]/, ''))).length >= count;
  });
}

// The clip to preselect (a ClipInfo's name), or '' when there are none.
// `clips`: ClipInfos in the pickers' order; `jointsOf(skeleton)`: its joint names.
export function defaultRetargetSource(clips, skeleton, jointsOf) {
  const other = clips.filter((c) => c.skeleton !== skeleton && !c.name.endsWith(`_on_${skeleton}`));
  const body = other.find((c) => looksLikeABody(jointsOf(c.skeleton)));
  return (body ?? other[0] ?? clips[0])?.name ?? '';
}
