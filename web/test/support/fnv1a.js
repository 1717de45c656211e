// FNV-1a 64 over the bytes of a typed array (little-endian, as the golden
// vectors and the C++ tests hash float arrays). BigInt for the 64-bit product.
export function fnv1a64(array) {
  const bytes = new Uint8Array(array.buffer, array.byteOffset, array.byteLength);
  const prime = 0x100000001b3n, mask = 0xffffffffffffffffn;
  let h = 0xcbf29ce484222325n;
  for (let i = 0; i < bytes.length; ++i) h = ((h ^ BigInt(bytes[i])) * prime) & mask;
  return h;
}
