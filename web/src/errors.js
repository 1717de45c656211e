// The decoder's one error type. `code` is the spec's error name
// (spec/README.md section 7: bad_magic, unsupported_version, truncated,
// trailing_bytes, face_count_mismatch, bad_count, bad_value, reserved_bits,
// bad_mesh, layout_unreachable_face), so callers can branch on it; the
// message says where.
export class GltfWarpError extends Error {
  constructor(code, detail = '') {
    super(detail ? `${code}: ${detail}` : code);
    this.name = 'GltfWarpError';
    this.code = code;
  }
}
