// At most one call in flight; while it runs only the latest request is kept
// (older ones are dropped unseen). Scrubbing, dragging and live switches all
// ask faster than the server answers; the user wants the newest answer, not
// a queue of stale ones.
export class LatestWins {
  // `task(value)`: an async function; it handles its own errors.
  constructor(task) {
    this.task = task;
    this.pending = false;
    this.wanted = undefined;
    this.running = null;  // the pump's promise while busy
  }

  get busy() {
    return this.running !== null || this.pending;
  }

  // Runs `task(value)` now, or after the call in flight (replacing any value
  // already waiting). The promise settles when nothing is left to run.
  request(value) {
    this.wanted = value;
    this.pending = true;
    if (!this.running) this.running = this.pump();
    return this.running;
  }

  // Drops the waiting value (the call in flight still finishes).
  cancel() {
    this.pending = false;
    this.wanted = undefined;
  }

  // Clears `running` in the same step as its last look at `pending` (not in
  // a later .finally()): a request made between the two would otherwise be
  // left waiting with no pump to run it.
  async pump() {
    try {
      while (this.pending) {
        const value = this.wanted;
        this.cancel();
        await this.task(value);
      }
    } finally {
      this.running = null;
    }
  }
}
