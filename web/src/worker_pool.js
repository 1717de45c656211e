// A few module workers that run decodePrimitive jobs, the least busy first
// (the pattern of DRACOLoader's worker pool). Without Worker (node, or
// workerLimit 0) jobs run inline on the calling thread.
import { decodePrimitive } from './decode_primitive.js';
import { GltfWarpError } from './errors.js';

export class WorkerPool {
  constructor(workerLimit = 4) {
    this.workerLimit = typeof Worker === 'undefined' ? 0 : workerLimit;
    this.workers = []; // { worker, pending: Map(id -> {resolve, reject}) }
    this.nextId = 1;
  }

  // job as decodePrimitive takes it; its arrays are transferred (the caller
  // passes copies it no longer needs).
  run(job) {
    if (this.workerLimit === 0) return Promise.resolve().then(() => decodePrimitive(job));
    const slot = this.pick();
    const id = this.nextId++;
    const transfer = [job.positions.buffer, job.indices.buffer, job.stream.buffer];
    if (job.normals) transfer.push(job.normals.buffer);
    for (const a of job.attributes ?? []) transfer.push(a.array.buffer);
    return new Promise((resolve, reject) => {
      slot.pending.set(id, { resolve, reject });
      slot.worker.postMessage({ id, job }, transfer);
    });
  }

  pick() {
    if (this.workers.length < this.workerLimit && this.workers.every((w) => w.pending.size > 0)) {
      const worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
      const slot = { worker, pending: new Map() };
      worker.onmessage = ({ data }) => {
        const p = slot.pending.get(data.id);
        slot.pending.delete(data.id);
        if (data.error) p.reject(new GltfWarpError(data.error.code, data.error.message.replace(/^\w+: /, '')));
        else p.resolve(data.result);
      };
      worker.onerror = (e) => {
        for (const p of slot.pending.values()) p.reject(new Error(`gltf-warp worker failed: ${e.message}`));
        slot.pending.clear();
      };
      this.workers.push(slot);
      return slot;
    }
    return this.workers.reduce((a, b) => (b.pending.size < a.pending.size ? b : a));
  }

  dispose() {
    for (const w of this.workers) w.worker.terminate();
    this.workers = [];
  }
}
