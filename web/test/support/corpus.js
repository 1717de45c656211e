// The corpus models the tests encode and decode with the CLI. Paths come from
// the environment (web/CMakeLists.txt sets them): GLTFWARP_CLI, GLTFWARP_CORPUS.
// On CI (CI=true) a missing CLI or corpus is a failure; elsewhere the tests
// skip with the reason.
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readdirSync, statSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { basename, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const onCi = process.env.CI === 'true';

// Returns a reason to skip (string) or null; throws on CI.
export function missing(what, ok) {
  if (ok) return null;
  if (onCi) throw new Error(`${what} is missing, and CI=true makes that a failure`);
  return `${what} is missing`;
}

export function cliPath() {
  return process.env.GLTFWARP_CLI ?? fileURLToPath(new URL('../../../build/gltf-warp', import.meta.url));
}

export function corpusDir() {
  return process.env.GLTFWARP_CORPUS ?? fileURLToPath(new URL('../../../../shared/corpus', import.meta.url));
}

// Every .gltf / .glb under the corpus, sorted: { name, path }.
export function corpusModels() {
  const out = [];
  const walk = (dir) => {
    for (const entry of readdirSync(dir).sort()) {
      const p = join(dir, entry);
      if (statSync(p).isDirectory()) walk(p);
      else if (/\.(gltf|glb)$/.test(entry)) out.push({ name: `${basename(join(dir, '..'))}-${entry}`.replace(/[^\w.-]/g, '_'), path: p });
    }
  };
  walk(corpusDir());
  return out;
}

// Encodes (every textured primitive implicit; low texel density, since the
// images do not matter for these tests and it keeps the warp fast) and
// decodes with the CLI. Returns { encoded, decoded } paths in `dir`.
// `extra`: more encode arguments; `tag` names the pair apart (model.tag.enc.glb).
export function encodeAndDecode(model, dir, extra = [], tag = '') {
  const cli = cliPath();
  const name = tag ? `${model.name}.${tag}` : model.name;
  const encoded = join(dir, `${name}.enc.glb`), decoded = join(dir, `${name}.dec.glb`);
  execFileSync(cli, ['encode', model.path, '-o', encoded, '--always-implicit', '--min-psnr', '0', '--texel-density', '0.25x', ...extra],
    { stdio: ['ignore', 'ignore', 'inherit'] });
  execFileSync(cli, ['decode', encoded, '-o', decoded], { stdio: ['ignore', 'ignore', 'inherit'] });
  return { encoded, decoded };
}

export function workDir() {
  return mkdtempSync(join(tmpdir(), 'gltf-warp-web-'));
}

export function prerequisites() {
  const three = fileURLToPath(new URL('../../node_modules/three/package.json', import.meta.url));
  return missing('web/node_modules (run npm ci in web/)', existsSync(three)) ??
    missing(`gltf-warp CLI (${cliPath()})`, existsSync(cliPath())) ??
    missing(`corpus (${corpusDir()})`, existsSync(corpusDir()));
}
