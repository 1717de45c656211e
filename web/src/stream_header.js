// Section 4.1 / 6.1 of spec/README.md: the stream header and the two section
// spans. Every count is checked against the bytes that remain before anything
// is sized by it.
import { GltfWarpError } from './errors.js';

const MAGIC = [0x47, 0x57, 0x55, 0x56]; // "GWUV"
export const FLAG_ROTATIONS = 0x01, FLAG_SCALES = 0x02, FLAG_SEEDS = 0x04, FLAG_METHODS = 0x08, FLAG_FINE = 0x10,
  FLAG_COTANGENT = 0x20;
const MAX_ATLAS = 65536, MAX_PAGES = 65536;

class ByteReader {
  constructor(bytes) {
    this.bytes = bytes;
    this.pos = 0;
  }
  left() {
    return this.bytes.length - this.pos;
  }
  u8(field) {
    if (this.left() < 1) throw new GltfWarpError('truncated', `stream ends in ${field}`);
    return this.bytes[this.pos++];
  }
  f32(field) {
    if (this.left() < 4) throw new GltfWarpError('truncated', `stream ends in ${field}`);
    const b = this.bytes, p = this.pos;
    this.pos += 4;
    return new DataView(b.buffer, b.byteOffset + p, 4).getFloat32(0, true);
  }
  // LEB128, at most 5 bytes, value < 2^32, minimal.
  varint(field) {
    let x = 0;
    for (let i = 0; i < 5; ++i) {
      const byte = this.u8(field);
      x += (byte & 0x7f) * 2 ** (7 * i);
      if (!(byte & 0x80)) {
        if (x > 0xffffffff || (i > 0 && byte === 0)) throw new GltfWarpError('bad_value', `${field} is not a minimal 32-bit varint`);
        return x;
      }
    }
    throw new GltfWarpError('bad_value', `${field} varint longer than 5 bytes`);
  }
  span(n, field) {
    if (n > this.left()) throw new GltfWarpError('truncated', `${field} runs past the stream`);
    const s = this.bytes.subarray(this.pos, this.pos + n);
    this.pos += n;
    return s;
  }
}

// Reads the header, checks it against the mesh's face count, and returns the
// fields plus the partition and placement byte spans (subarrays of `bytes`).
export function readHeader(bytes, meshFaceCount) {
  if (bytes.length < 4) {
    const prefix = MAGIC.slice(0, bytes.length).every((m, i) => bytes[i] === m);
    throw new GltfWarpError(prefix ? 'truncated' : 'bad_magic', 'stream shorter than its magic');
  }
  if (!MAGIC.every((m, i) => bytes[i] === m)) throw new GltfWarpError('bad_magic');
  const r = new ByteReader(bytes);
  r.pos = 4;
  const major = r.u8('version_major'), minor = r.u8('version_minor');
  if (major !== 1 || minor > 4) throw new GltfWarpError('unsupported_version', `version ${major}.${minor}`);
  const flags = r.u8('flags');
  const known = FLAG_ROTATIONS | FLAG_SCALES | (minor >= 1 ? FLAG_SEEDS : 0) | (minor >= 2 ? FLAG_METHODS : 0) |
    (minor >= 3 ? FLAG_FINE : 0) | (minor >= 4 && flags & FLAG_METHODS ? FLAG_COTANGENT : 0);
  if (flags & ~known) throw new GltfWarpError('reserved_bits', `flags 0x${flags.toString(16)}`);
  const h = { major, minor, flags };
  h.faceCount = r.varint('face_count');
  h.tau = r.f32('tau');
  h.texelScale = r.f32('texel_scale');
  h.atlasWidth = r.varint('atlas_width');
  h.atlasHeight = r.varint('atlas_height');
  h.pageCount = r.varint('page_count');
  h.patchCount = r.varint('patch_count');
  for (const [name, v] of [['tau', h.tau], ['texel_scale', h.texelScale]])
    if (!Number.isFinite(v) || !(v > 0)) throw new GltfWarpError('bad_value', `${name} ${v}`);
  if (h.atlasWidth < 1 || h.atlasWidth > MAX_ATLAS || h.atlasHeight < 1 || h.atlasHeight > MAX_ATLAS)
    throw new GltfWarpError('bad_count', `atlas ${h.atlasWidth} x ${h.atlasHeight}`);
  if (h.pageCount < 1 || h.pageCount > MAX_PAGES) throw new GltfWarpError('bad_count', `page_count ${h.pageCount}`);
  if (h.faceCount === 0 ? h.patchCount !== 0 : h.patchCount < 1 || h.patchCount > h.faceCount)
    throw new GltfWarpError('bad_count', `patch_count ${h.patchCount} for ${h.faceCount} faces`);
  if (flags & FLAG_METHODS) { // 1.2: the solve's step counts (section 6.7)
    h.solve = { tutteSteps: r.varint('tutte_steps'), arapRounds: r.varint('arap_rounds'), arapSteps: r.varint('arap_steps'),
      cotangent: (flags & FLAG_COTANGENT) !== 0 }; // 1.4: ARAP on cotangent weights
    if (h.solve.tutteSteps > 1024 || h.solve.arapRounds > 64 || h.solve.arapSteps > 1024)
      throw new GltfWarpError('bad_value', 'solve parameters out of range');
  }
  if (h.faceCount !== meshFaceCount)
    throw new GltfWarpError('face_count_mismatch', `stream has ${h.faceCount} faces, mesh ${meshFaceCount}`);
  h.partition = r.span(r.varint('partition_size'), 'partition section');
  h.placements = r.span(r.varint('placement_size'), 'placement section');
  if (r.left() !== 0) throw new GltfWarpError('trailing_bytes', `${r.left()} bytes after the placement section`);
  return h;
}
