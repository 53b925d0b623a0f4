// The REST gateway, as the viewer uses it. Every call rejects with an Error
// carrying the server's message (and its gRPC `code`).

async function call(path, options = {}) {
  const res = await fetch(path, options);
  const body = await res.json().catch(() => null);
  if (!res.ok) {
    const error = new Error(body?.message ?? `${res.status} ${res.statusText}`);
    error.code = body?.code;
    throw error;
  }
  return body;
}

const clipPath = (clip) => `/v1/clips/${encodeURIComponent(clip)}`;

export async function listClips() {
  return (await call('/v1/clips')).clips;
}

export function getClip(clip) {
  return call(clipPath(clip));
}

export function getSkeleton(skeleton) {
  return call(`/v1/skeletons/${encodeURIComponent(skeleton)}`);
}

const postJson = (body) => ({
  method: 'POST',
  headers: { 'Content-Type': 'application/json' },
  body: JSON.stringify(body),
});

// Poses of every joint at `times`, in `space` ('WORLD' or 'LOCAL').
export function evaluate(clip, times, space = 'WORLD') {
  return call(`${clipPath(clip)}:evaluate`, postJson({ times, space }));
}

// One inverse kinematics solve (a SolveIkRequest as JSON, less the skeleton).
export function solveIk(skeleton, request) {
  return call(`/v1/skeletons/${encodeURIComponent(skeleton)}:solveIk`, postJson(request));
}

// Plays `clip` over Server-Sent Events. `onFrame(frame)` gets each PoseFrame,
// `onEnd(status)` the final {code, message} (code 0: the clip ended). Returns
// a function that stops the stream.
export function streamClip(clip, { startTime = 0, speed = 1, fps = 30, loop = true }, onFrame, onEnd) {
  const query = new URLSearchParams({
    startTime: String(startTime),
    speed: String(speed),
    fps: String(fps),
    loop: String(loop),
    space: 'WORLD',
  });
  const source = new EventSource(`${clipPath(clip)}:stream?${query}`);
  let open = true;
  const close = () => {
    open = false;
    source.close();
  };
  source.onmessage = (event) => onFrame(JSON.parse(event.data));
  source.addEventListener('status', (event) => {
    close();  // the stream is over: no automatic reconnect
    onEnd(JSON.parse(event.data));
  });
  source.onerror = () => {
    if (!open) return;
    close();
    onEnd({ code: 14, message: 'the pose stream was interrupted' });
  };
  return close;
}
