// A skeleton artifact as the server serves it with ?format=json
// ({"nodes": [[x, y, z], ...], "edges": [[i, j], ...], "radii"?}, 0-based;
// io/skeleton_io.h), checked: a bad file is an error sentence, never a crash.

export interface SkeletonData {
  /** x, y, z per node. */
  nodes: Float32Array;
  /** Node index pairs. */
  edges: Uint32Array;
}

export function parseSkeleton(json: unknown): SkeletonData {
  if (!json || typeof json !== 'object') throw new Error('a skeleton is a JSON object');
  const { nodes, edges } = json as { nodes?: unknown; edges?: unknown };
  if (!Array.isArray(nodes)) throw new Error('a skeleton needs a "nodes" array');
  const out = new Float32Array(nodes.length * 3);
  nodes.forEach((p, i) => {
    if (!Array.isArray(p) || p.length !== 3 || !p.every((v) => typeof v === 'number' && Number.isFinite(v))) throw new Error(`node ${i} is not [x, y, z]`);
    out.set(p as number[], i * 3);
  });
  const list = edges === undefined ? [] : edges;
  if (!Array.isArray(list)) throw new Error('"edges" is not an array');
  const e = new Uint32Array(list.length * 2);
  list.forEach((pair, i) => {
    if (!Array.isArray(pair) || pair.length !== 2 || !pair.every((v) => Number.isInteger(v) && v >= 0 && v < nodes.length))
      throw new Error(`edge ${i} does not join two of the ${nodes.length} nodes`);
    e.set(pair as number[], i * 2);
  });
  return { nodes: out, edges: e };
}

/** Node degrees: 1 at an end, 3+ at a branch node. */
export function nodeDegrees(s: SkeletonData): Uint32Array {
  const d = new Uint32Array(s.nodes.length / 3);
  for (const n of s.edges) d[n]! += 1;
  return d;
}
