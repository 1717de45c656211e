// Serves web/ (the viewer, the plugin, node_modules/three) on 127.0.0.1:
//   node web/serve.mjs [port]   then open http://127.0.0.1:<port>/viewer.html
import { fileURLToPath } from 'node:url';
import { serveStatic } from './test/support/static_server.js';

const { url } = await serveStatic({ '/': fileURLToPath(new URL('.', import.meta.url)) }, Number(process.argv[2] ?? 8080));
console.log(`gltf-warp viewer: ${url}/viewer.html (Ctrl-C to stop)`);
