// Section 5 of spec/README.md: the LZMA-style range decoder (I. Pavlov, LZMA
// SDK) with 16-bit adaptive contexts, uniform symbols by division, and up to
// four implicit zero bytes past the end of a section.
//
// 32-bit unsigned state in JavaScript numbers: every product and quotient
// here stays below 2^53, so double arithmetic is exact; `>>> 0` brings the
// wrapping shifts of the spec back to unsigned 32 bits. Never reads outside
// `bytes`; the first error throws (the C++ keeps the first error sticky,
// which yields the same status).
import { GltfWarpError } from './errors.js';

const TOP = 1 << 24;
const MAX_OVERREAD = 4;
const PROB_MIN = 32, PROB_MAX = 65536 - 32;

// A context's state lives in two typed arrays so a model is one allocation:
// contexts(n) gives n contexts starting at p0 = 32768, count = 0.
export function contexts(n) {
  return { p0: new Uint32Array(n).fill(32768), count: new Uint8Array(n) };
}

export class RangeDecoder {
  constructor(bytes) {
    this.bytes = bytes;
    this.pos = 0;
    this.range = 0xffffffff;
    this.code = 0;
    for (let i = 0; i < 4; ++i) this.code = ((this.code << 8) | this.nextByte()) >>> 0;
  }

  nextByte() {
    const p = this.pos++;
    if (p < this.bytes.length) return this.bytes[p];
    if (p - this.bytes.length >= MAX_OVERREAD) throw new GltfWarpError('truncated', 'range-coded section ends early');
    return 0;
  }

  normalize() {
    while (this.range < TOP) {
      this.range = (this.range << 8) >>> 0;
      this.code = ((this.code << 8) | this.nextByte()) >>> 0;
    }
  }

  split(p0) {
    const bound = (this.range >>> 16) * p0; // < 2^32, exact
    let bit;
    if (this.code < bound) {
      this.range = bound;
      bit = 0;
    } else {
      this.code -= bound;
      this.range -= bound;
      bit = 1;
    }
    this.normalize();
    return bit;
  }

  // Adaptive bit with context i of model ctx (5.3).
  bit(ctx, i) {
    const p0 = ctx.p0[i];
    const bit = this.split(p0);
    const count = ctx.count[i];
    const shift = 32 - Math.clz32(count + 1); // bit_width(count + 1)
    let p = bit === 0 ? p0 + ((65536 - p0) >>> shift) : p0 - (p0 >>> shift);
    if (p < PROB_MIN) p = PROB_MIN;
    else if (p > PROB_MAX) p = PROB_MAX;
    ctx.p0[i] = p;
    if (count < 63) ctx.count[i] = count + 1;
    return bit;
  }

  equiprobable() {
    return this.split(32768);
  }

  // 5.5: n <= 65536.
  uniform(n) {
    if (n <= 1) return 0;
    const r = Math.floor(this.range / n); // exact: both < 2^32
    const q = Math.floor(this.code / r);
    if (q >= n) throw new GltfWarpError('bad_value', `uniform symbol ${q} not below ${n}`);
    this.code -= q * r;
    this.range = r;
    this.normalize();
    return q;
  }

  // 5.6: n <= 2^32, as a high and a low 16-bit part.
  uniform32(n) {
    if (n <= 65536) return this.uniform(n);
    const hn = Math.floor((n - 1) / 65536) + 1;
    const hi = this.uniform(hn);
    const ln = hi === hn - 1 ? ((n - 1) % 65536) + 1 : 65536;
    return hi * 65536 + this.uniform(ln);
  }

  // 5.7: Exp-Golomb with 16 prefix contexts; w reaches 2^33 (exact in a double).
  expGolomb(prefix) {
    let k = 0;
    while (k < 32 && this.bit(prefix, Math.min(k, 15)) === 1) ++k;
    let w = 1;
    for (let i = 0; i < k; ++i) w = w * 2 + this.equiprobable();
    if (w - 1 >= 2 ** 32) throw new GltfWarpError('bad_value', 'Exp-Golomb value too large');
    return w - 1;
  }

  // 5.1: every byte of the section must have been read.
  finish(section) {
    if (this.pos < this.bytes.length) throw new GltfWarpError('trailing_bytes', `unread bytes at the end of the ${section} section`);
  }
}
