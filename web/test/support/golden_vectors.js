// The golden vectors of spec section 9, read from tests/golden/*.h (the C++
// headers stay the one copy), and the golden mesh of
// tests/test_bitstream_golden.cpp rebuilt with the same float operations.
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';

const repo = fileURLToPath(new URL('../../../', import.meta.url));

export function goldenVector(name) {
  const text = readFileSync(`${repo}tests/golden/uvmap_v${name}.h`, 'utf8');
  const body = text.split(`kUvMapV${name}[] = {`)[1].split('};')[0];
  const bytes = Uint8Array.from(body.match(/0x[0-9a-f]{2}/g).map((h) => parseInt(h, 16)));
  const hash = BigInt(text.match(new RegExp(`kUvMapV${name}UvHash = (0x[0-9a-f]+)`))[1]);
  return { bytes, hash };
}

// 12 x 8 grid of quads on the saddle z = 0.75 x y, in float like the C++.
export function goldenMesh() {
  const nx = 12, ny = 8, f = Math.fround;
  const positions = [], indices = [];
  for (let j = 0; j <= ny; ++j)
    for (let i = 0; i <= nx; ++i) {
      const x = f(i / 12), y = f(j / 8);
      positions.push(x, y, f(f(0.75 * x) * y));
    }
  for (let j = 0; j < ny; ++j)
    for (let i = 0; i < nx; ++i) {
      const a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1;
      indices.push(a, b, c + 1, a, c + 1, c);
    }
  return { positions: Float32Array.from(positions), indices: Uint32Array.from(indices) };
}
