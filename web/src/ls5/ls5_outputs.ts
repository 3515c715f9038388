// The LS5's arithmetic of §8 the page shows live, as pure functions (the C++ twins are in
// include/rangekit/ls5/formulas.hpp; docs/conformance.md L8, L9, L10, L23 read the formulas).
// Codes are the 0...50000 result codes of §8.9; 65534 = no measurement yet, 65535 = no signal.

export const MAX_CODE = 50000;
export const NO_MEASUREMENT_YET = 65534;
export const NO_SIGNAL = 65535;

export interface AnalogRange {
  min: number;  // A_min
  max: number;  // A_max
  unit: string;
}

// §8.10 "for a 4-20 mA current output, it's 4 mA ... 20 mA"; table 3.1's other outputs (L25).
export const ANALOG_RANGES: Record<string, AnalogRange & { label: string }> = {
  '4-20mA': { min: 4, max: 20, unit: 'mA', label: '4–20 mA (I4)' },
  '0-20mA': { min: 0, max: 20, unit: 'mA', label: '0–20 mA (I0)' },
  '0-10V': { min: 0, max: 10, unit: 'V', label: '0–10 V (U10)' },
};

// Formula 8.1: distance = range · code / 50000 (pure result, from the start of the range).
export function distanceMm(code: number, rangeMm: number): number {
  return (rangeMm * code) / MAX_CODE;
}

// Formula 8.2: derivative = range · (code − 25000) / 50000.
export function derivativeMm(code: number, rangeMm: number): number {
  return (rangeMm * (code - 25000)) / MAX_CODE;
}

// Rounding to the nearest integer, halves away from zero (§8.14 "int", L10/L23).
function roundHalfAway(value: number): number {
  return Math.sign(value) * Math.round(Math.abs(value));
}

// Formula 8.5: code = distance / range · 50000.
export function codeFromDistance(distanceMm: number, rangeMm: number): number {
  return roundHalfAway((distanceMm / rangeMm) * MAX_CODE);
}

// Formula 8.3 as L8 reads it: linear between K_n and K_v, held at the ends outside, inverted
// when K_v < K_n, A_min when K_v = K_n. For 65535 (no signal), the extreme nearer the output of
// the last result (A_min if none); for 65534 (nothing measured yet), A_min (§8.2).
export function analogOutput(range: AnalogRange, lower: number, upper: number, code: number,
  lastResultCode?: number): number {
  if (code === NO_MEASUREMENT_YET) return range.min;
  if (code === NO_SIGNAL) {
    if (lastResultCode === undefined || lastResultCode > MAX_CODE) return range.min;
    const last = analogOutput(range, lower, upper, lastResultCode);
    return last < (range.min + range.max) / 2 ? range.min : range.max;
  }
  if (lower === upper) return range.min;
  if (lower < upper) {
    if (code <= lower) return range.min;
    if (code >= upper) return range.max;
  } else {
    if (code <= upper) return range.max;
    if (code >= lower) return range.min;
  }
  return range.min + ((range.max - range.min) * (code - lower)) / (upper - lower);
}

// Parameter 15's digit for one output: 0 disabled, 1 enabled with N = 0, 2 enabled with N = 1.
export interface DiscreteSetting {
  enabled: boolean;
  initial: 0 | 1;  // N
}

// Parameter 15 as two hex digits ("12": output 1 digit 1, output 2 digit 2).
export function decodeDiscreteOutputs(byte: string): [DiscreteSetting, DiscreteSetting] | null {
  if (!/^[0-2]{2}$/.test(byte)) return null;
  const one = (digit: string): DiscreteSetting => ({ enabled: digit !== '0', initial: digit === '2' ? 1 : 0 });
  return [one(byte[0]), one(byte[1])];
}

// Formula 8.4: OC = not N for K_OC1 ≤ K ≤ K_OC2, N otherwise, also for 65534/65535 (§8.11,
// L9); a disabled output is 0.
export function discreteOutput(setting: DiscreteSetting, firstSwing: number, secondSwing: number,
  code: number): 0 | 1 {
  if (!setting.enabled) return 0;
  const inside = firstSwing <= code && code <= secondSwing;
  return (inside ? 1 - setting.initial : setting.initial) as 0 | 1;
}

// Formulas 8.6 and 8.7: G_min/G_max = int(K ∓ D/2), held within 0...50000.
export function latchLimits(code: number, fixedRange: number): { lower: number; upper: number } {
  const clamp = (value: number) => Math.min(MAX_CODE, Math.max(0, roundHalfAway(value)));
  return { lower: clamp(code - fixedRange / 2), upper: clamp(code + fixedRange / 2) };
}

// What FX does under each latching byte (table 9.2, parameter 1F; §8.14, L10).
export const LATCHING_EFFECT: Record<string, string> = {
  '00': 'Latching disabled: the sync input and FX do not latch.',
  '01': 'FX records the result in the latch only.',
  '02': 'FX also recalculates the analog output limits (11–14) from the fixed range of the analog output.',
  '03': 'As 02, and the new analog limits are written to the ROM.',
  '04': 'FX also recalculates the 1st discrete output swings (16–19) from the fixed range of the discrete outputs.',
  '05': 'As 04, and the new swings are written to the ROM.',
  '06': 'FX also recalculates the 2nd discrete output swings (1A–1D) from the fixed range of the discrete outputs.',
  '07': 'As 06, and the new swings are written to the ROM.',
  '08': 'FX also sets the first swing of output 1 to G_min and the second swing of output 2 to G_max.',
  '09': 'As 08, and the new swings are written to the ROM.',
};
