// Module worker: runs decodePrimitive off the main thread (as DRACOLoader
// decodes in its workers) and hands the typed arrays back by transfer.
import { decodePrimitive } from './decode_primitive.js';

self.onmessage = (event) => {
  const { id, job } = event.data;
  try {
    const r = decodePrimitive(job);
    const transfer = [r.index.buffer, r.origin.buffer, r.uv.buffer, r.patchOfVertex.buffer];
    if (r.tangent) transfer.push(r.tangent.buffer);
    if (r.positions) transfer.push(r.positions.buffer);
    for (const a of r.attributes ?? []) transfer.push(a.buffer);
    self.postMessage({ id, result: r }, transfer);
  } catch (error) {
    self.postMessage({ id, error: { code: error.code ?? 'internal', message: String(error.message ?? error) } });
  }
};
