// The BM icon (U124). §2: "BM (Basic Measurement): The ULS is producing valid measurements
// more than once every two seconds." Judged by the interval between the last two valid
// measurements, so a steady rate faster than one per 2 s keeps it lit without a flicker.
export const BASIC_INTERVAL_MS = 2000;

export class BasicMeasurement {
  private previous: number | undefined;
  private last: number | undefined;

  // A valid measurement (a distance, a binning target or a look-down ON/OFF) at `time` (ms).
  valid(time: number): void {
    this.previous = this.last;
    this.last = time;
  }

  // Lit when the last two valid measurements came less than 2 s apart and the last is less
  // than 2 s old: once 2 s pass without one, the unit no longer measures more often than that.
  lit(now: number): boolean {
    if (this.last === undefined || this.previous === undefined) return false;
    return this.last - this.previous < BASIC_INTERVAL_MS && now - this.last < BASIC_INTERVAL_MS;
  }
}
