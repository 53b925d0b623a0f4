// LatestWins in node: only the newest waiting value runs after the call in
// flight, and a request made at any moment while the last call finishes
// (here: after 0 to 8 microtask hops from its answer) is run, never left
// waiting with no pump.   node latest_wins_test.mjs
import { LatestWins } from '../../src/latest_wins.js';

let failed = false;
function check(condition, message) {
  console.log(`${condition ? 'ok' : 'FAIL'}: ${message}`);
  if (!condition) failed = true;
}

const settle = () => new Promise((resolve) => setTimeout(resolve, 0));

// While one call runs, 2, 3 and 4 arrive: 4 runs next, 2 and 3 never.
{
  const ran = [];
  let release;
  const wins = new LatestWins(async (v) => {
    ran.push(v);
    if (v === 1) await new Promise((resolve) => (release = resolve));
  });
  wins.request(1);
  for (const v of [2, 3, 4]) wins.request(v);
  check(wins.busy, 'busy while a call runs');
  release();
  await wins.running;
  await settle();
  check(JSON.stringify(ran) === '[1,4]' && !wins.busy, `the latest waiting value runs after the call in flight: ${JSON.stringify(ran)}`);
}

// The call in flight answers; `hops` microtasks later (as an event listener
// awaiting that answer would) the next value is requested.
for (let hops = 0; hops <= 8; ++hops) {
  const ran = [];
  let answered;
  const answer = new Promise((resolve) => (answered = resolve));
  const wins = new LatestWins(async (v) => {
    ran.push(v);
    if (v === 'first') answered();
  });
  answer.then(async () => {
    for (let i = 0; i < hops; ++i) await null;
    wins.request('second');
  });
  wins.request('first');
  await settle();
  await settle();
  check(ran.join() === 'first,second' && !wins.busy,
        `a request ${hops} microtasks after the last answer runs: ${ran.join()}${wins.busy ? ' (left waiting)' : ''}`);
}

process.exit(failed ? 1 : 0);
