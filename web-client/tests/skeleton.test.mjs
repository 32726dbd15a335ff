// Unit test of src/api/skeleton.ts: the JSON the server serves for a
// skeleton artifact, and the errors a bad one gives.  `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import ts from 'typescript';

const here = path.dirname(fileURLToPath(import.meta.url));
const source = fs.readFileSync(path.join(here, '..', 'src', 'api', 'skeleton.ts'), 'utf8');
const { outputText } = ts.transpileModule(source, {
  compilerOptions: { module: ts.ModuleKind.ESNext, target: ts.ScriptTarget.ES2022 },
});
const { parseSkeleton, nodeDegrees } = await import(`data:text/javascript;base64,${Buffer.from(outputText).toString('base64')}`);

test('a Y skeleton parses, with its ends and branch node', () => {
  const s = parseSkeleton({
    nodes: [
      [0, 0, 0],
      [0, 1, 0],
      [-1, 2, 0],
      [1, 2, 0],
    ],
    edges: [
      [0, 1],
      [1, 2],
      [1, 3],
    ],
  });
  assert.deepEqual([...s.nodes.subarray(3, 6)], [0, 1, 0]);
  assert.deepEqual([...nodeDegrees(s)], [1, 3, 1, 1]);
});

test('bad skeletons are errors that say what is wrong', () => {
  assert.throws(() => parseSkeleton(null), /JSON object/);
  assert.throws(() => parseSkeleton({ edges: [] }), /"nodes"/);
  assert.throws(() => parseSkeleton({ nodes: [[0, 0]] }), /node 0/);
  assert.throws(() => parseSkeleton({ nodes: [[0, 0, 0]], edges: [[0, 1]] }), /edge 0/);
  assert.throws(
    () =>
      parseSkeleton({
        nodes: [
          [0, 0, 0],
          [1, 1, 1],
        ],
        edges: [[0, -1]],
      }),
    /edge 0/,
  );
});
