// The ULS page's BM icon (U124), its logic run here (node) on the page's own module, bundled as
// the page gets it, with measurement times typed by hand. No browser: virtual time only.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import * as esbuild from 'esbuild';

const bundle = await esbuild.build({ entryPoints: ['src/uls/basic_measurement.ts'], bundle: true, format: 'esm', write: false });
const { BasicMeasurement } = await import(`data:text/javascript;base64,${Buffer.from(bundle.outputFiles[0].text).toString('base64')}`);

// The icon at every 100 ms from `from` to `to` (ms), as a list of booleans.
const litBetween = (basic, from, to) => {
  const seen = [];
  for (let now = from; now <= to; now += 100) seen.push(basic.lit(now));
  return seen;
};

test('BM stays lit while valid measurements come every 1.5 s', () => {
  // §2 "BM (Basic Measurement): The ULS is producing valid measurements more than once every
  // two seconds." One every 1.5 s is more than once every 2 s: lit at every moment, no flicker.
  const basic = new BasicMeasurement();
  basic.valid(0);
  // One measurement gives no rate yet: dark until the second.
  assert.ok(litBetween(basic, 0, 1400).every((lit) => !lit));
  const lit = [];
  for (let time = 1500; time <= 9000; time += 1500) {
    basic.valid(time);
    lit.push(...litBetween(basic, time, time + 1400));
  }
  lit.push(...litBetween(basic, 10500, 10900));
  assert.equal(lit.length, 95);  // every 100 ms from 1.5 s to 10.9 s
  assert.ok(lit.every(Boolean), 'dark at some moment between 1.5 s and 10.9 s');
  // "two seconds": 2 s after the last measurement (9 s) with none since, it goes dark.
  assert.equal(basic.lit(11000), false);
});

test('BM stays dark when valid measurements come every 2.5 s, or every 2 s exactly', () => {
  for (const interval of [2500, 2000]) {
    const basic = new BasicMeasurement();
    const seen = [];
    for (let time = 0; time <= 10 * interval; time += interval) {
      basic.valid(time);
      seen.push(...litBetween(basic, time, time + interval - 100));
    }
    assert.ok(seen.every((lit) => !lit), `lit at some moment with one measurement every ${interval} ms`);
  }
});
