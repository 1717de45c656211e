// Appendix A of spec/README.md: the rotation sine table and the quarter-octave
// scale table, as the exact binary64 values the spec writes in hexadecimal.
// JavaScript has no hexadecimal float literal, so each is rebuilt here from
// its digits exactly (53-bit integer times a power of two; no rounding).

function hexFloat(text) {
  const m = /^(-?)0x([01])\.([0-9a-f]{13})p([+-]\d+)$/.exec(text);
  if (!m) throw new Error(`bad hex float ${text}`);
  const mantissa = Number(BigInt(`0x${m[2]}${m[3]}`)); // < 2^53: exact
  const value = mantissa * 2 ** (Number(m[4]) - 52); // power of two: exact
  return m[1] ? -value : value;
}

// S[i] = sin(2 pi i / 256), i = 0..64.
const SINE = [
  '0x0.0000000000000p+0', '0x1.92155f7a3667ep-6', '0x1.91f65f10dd814p-5', '0x1.2d52092ce19f6p-4',
  '0x1.917a6bc29b42cp-4', '0x1.f564e56a9730ep-4', '0x1.2c8106e8e613ap-3', '0x1.5e214448b3fc6p-3',
  '0x1.8f8b83c69a60bp-3', '0x1.c0b826a7e4f63p-3', '0x1.f19f97b215f1bp-3', '0x1.111d262b1f677p-2',
  '0x1.294062ed59f06p-2', '0x1.4135c94176601p-2', '0x1.58f9a75ab1fddp-2', '0x1.7088530fa459fp-2',
  '0x1.87de2a6aea963p-2', '0x1.9ef7943a8ed8ap-2', '0x1.b5d1009e15cc0p-2', '0x1.cc66e9931c45ep-2',
  '0x1.e2b5d3806f63bp-2', '0x1.f8ba4dbf89abap-2', '0x1.073879922ffeep-1', '0x1.11eb3541b4b23p-1',
  '0x1.1c73b39ae68c8p-1', '0x1.26d054cdd12dfp-1', '0x1.30ff7fce17035p-1', '0x1.3affa292050b9p-1',
  '0x1.44cf325091dd6p-1', '0x1.4e6cabbe3e5e9p-1', '0x1.57d69348ceca0p-1', '0x1.610b7551d2cdfp-1',
  '0x1.6a09e667f3bcdp-1', '0x1.72d0837efff96p-1', '0x1.7b5df226aafafp-1', '0x1.83b0e0bff976ep-1',
  '0x1.8bc806b151741p-1', '0x1.93a22499263fbp-1', '0x1.9b3e047f38741p-1', '0x1.a29a7a0462782p-1',
  '0x1.a9b66290ea1a3p-1', '0x1.b090a58150200p-1', '0x1.b728345196e3ep-1', '0x1.bd7c0ac6f952ap-1',
  '0x1.c38b2f180bdb1p-1', '0x1.c954b213411f5p-1', '0x1.ced7af43cc773p-1', '0x1.d4134d14dc93ap-1',
  '0x1.d906bcf328d46p-1', '0x1.ddb13b6ccc23cp-1', '0x1.e212104f686e5p-1', '0x1.e6288ec48e112p-1',
  '0x1.e9f4156c62ddap-1', '0x1.ed740e7684963p-1', '0x1.f0a7efb9230d7p-1', '0x1.f38f3ac64e589p-1',
  '0x1.f6297cff75cb0p-1', '0x1.f8764fa714ba9p-1', '0x1.fa7557f08a517p-1', '0x1.fc26470e19fd3p-1',
  '0x1.fd88da3d12526p-1', '0x1.fe9cdad01883ap-1', '0x1.ff621e3796d7ep-1', '0x1.ffd886084cd0dp-1',
  '0x1.0000000000000p+0',
].map((s) => (s === '0x0.0000000000000p+0' ? 0 : hexFloat(s)));

// T[k] = 2^(k/4), k = 0..3.
const QUARTER_OCTAVE = ['0x1.0000000000000p+0', '0x1.306fe0a31b715p+0', '0x1.6a09e667f3bcdp+0',
  '0x1.ae89f995ad3adp+0'].map(hexFloat);

export const ROTATION_STEPS = 256;

// [cos, sin] of rotation code r (A.1): quadrant symmetry over one table.
export function rotationCosSin(r) {
  r %= ROTATION_STEPS;
  const q = Math.floor(r / 64), i = r % 64;
  const c0 = SINE[64 - i], s0 = SINE[i];
  switch (q) {
    case 0: return [c0, s0];
    case 1: return [-s0, c0];
    case 2: return [-c0, -s0];
    default: return [s0, -c0];
  }
}

// 2^(step/4) for -32 <= step <= 32 (A.2): T[k] * 2^e with step = 4e + k,
// e by floor division; the power of two is exact.
export function patchScale(step) {
  const e = Math.floor(step / 4), k = step - 4 * e;
  return QUARTER_OCTAVE[k] * 2 ** e;
}
