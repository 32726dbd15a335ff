// Unit tests of src/api/frames.ts (the binary frame header of protocol/API.md),
// run with node's own test runner: `npm run test:unit`.
//
// The first two tests read every sample frame in tests/data/frames/ (written by
// the server's tests from protocol/frames.cpp), so that both sides are checked
// against the same bytes. Each NAME.bin has a NAME.json sidecar with the
// expected header fields as API.md names them (`total_bytes` is accepted for
// `total`), optionally under a "header" key; `chunk_bytes` is the size of this
// frame's chunk. Keys about the whole payload, checked once all the chunks of
// a request are joined: `payload_file` (a file beside the frames holding the
// payload), `payload_sha256`, and `vertices` / `faces` (the Draco payload is
// decoded with draco3d, the decoder the viewer's worker uses). A sidecar with
// "valid": false (or an "error" key) marks a frame that must be rejected.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createHash } from 'node:crypto';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { importTs } from './ts_module.mjs';
import draco3d from 'draco3d';

const here = path.dirname(fileURLToPath(import.meta.url));
const webClient = path.resolve(here, '..');
const repo = path.resolve(webClient, '..');
const samplesDir = path.join(repo, 'tests', 'data', 'frames');

// frames.ts is pure TypeScript with no imports: strip its types and load it.
const frames = await importTs('api/frames.ts');
const { decodeFrame, decodeFrameHeader, encodeFrame, ChunkAssembler, FrameError, FRAME_HEADER_BYTES } = frames;

// Sidecar key -> FrameHeader field.
const HEADER_KEYS = {
  magic: 'magic',
  version: 'version',
  kind: 'kind',
  request_id: 'request_id',
  chunk_index: 'chunk_index',
  chunk_count: 'chunk_count',
  header_bytes: 'header_bytes',
  total: 'total',
  total_bytes: 'total',
  total_payload_bytes: 'total',
};
const KIND_NAMES = { draco_mesh: 1, draco: 1 };
const CHUNK_SIZE_KEYS = ['chunk_bytes', 'chunk_size'];
const CHUNK_HASH_KEYS = ['chunk_sha256'];
// Checked by the second test, on the joined payload.
const WHOLE_PAYLOAD_KEYS = ['payload_file', 'payload_sha256', 'vertices', 'faces'];

const sha256 = (bytes) => createHash('sha256').update(bytes).digest('hex');

function readSidecar(file) {
  const sidecar = JSON.parse(fs.readFileSync(file, 'utf8'));
  return sidecar.header && typeof sidecar.header === 'object' ? { ...sidecar, ...sidecar.header } : sidecar;
}

const expectsRejection = (expected) => expected.valid === false || 'error' in expected || 'expect_error' in expected;

function samplePairs() {
  if (!fs.existsSync(samplesDir)) return [];
  return fs
    .readdirSync(samplesDir)
    .filter((f) => f.endsWith('.bin'))
    .sort()
    .map((bin) => ({
      name: bin.slice(0, -4),
      bin: path.join(samplesDir, bin),
      json: path.join(samplesDir, bin.slice(0, -4) + '.json'),
    }));
}

test('sample frames in tests/data/frames/ decode to their sidecar fields', async (t) => {
  const pairs = samplePairs();
  assert.ok(pairs.length > 0, `no sample frames (*.bin with a *.json sidecar) in ${samplesDir}; the server's tests write them`);
  for (const pair of pairs) {
    await t.test(pair.name, () => {
      assert.ok(fs.existsSync(pair.json), `${pair.name}.bin has no ${pair.name}.json sidecar`);
      const bytes = new Uint8Array(fs.readFileSync(pair.bin));
      const expected = readSidecar(pair.json);

      if (expectsRejection(expected)) {
        assert.throws(() => decodeFrame(bytes), FrameError, `${pair.name}.bin should be rejected`);
        return;
      }

      const { header, payload } = decodeFrame(bytes);
      let compared = 0;
      for (const [key, value] of Object.entries(expected)) {
        const field = HEADER_KEYS[key];
        if (field) {
          const want = field === 'kind' && typeof value === 'string' ? KIND_NAMES[value] : value;
          assert.equal(header[field], want, `${pair.name}: ${key}`);
          ++compared;
        } else if (CHUNK_SIZE_KEYS.includes(key)) {
          assert.equal(payload.byteLength, value, `${pair.name}: ${key}`);
        } else if (CHUNK_HASH_KEYS.includes(key)) {
          assert.equal(sha256(payload), value, `${pair.name}: ${key}`);
        } else if (!WHOLE_PAYLOAD_KEYS.includes(key) && key !== 'header' && key !== 'valid') {
          t.diagnostic(`${pair.name}.json: key "${key}" not checked`);
        }
      }
      assert.ok(compared >= 3, `${pair.name}.json names only ${compared} header fields; expected the fields of API.md`);
      // Fields the sidecar may leave out still obey the contract.
      assert.equal(header.magic, 'CGVF');
      assert.equal(header.version, 1);
      assert.equal(header.header_bytes, FRAME_HEADER_BYTES);
      assert.ok(payload.byteLength <= 4 * 1024 * 1024, 'a chunk payload is at most 4 MiB');
    });
  }
});

test('sample frames of one request join into their payload, which draco3d decodes', async (t) => {
  const byRequest = new Map();
  for (const pair of samplePairs()) {
    if (!fs.existsSync(pair.json)) continue; // the first test reports it
    const expected = readSidecar(pair.json);
    if (expectsRejection(expected)) continue;
    const frame = decodeFrame(new Uint8Array(fs.readFileSync(pair.bin)));
    const id = frame.header.request_id;
    if (!byRequest.has(id)) byRequest.set(id, []);
    byRequest.get(id).push({ name: pair.name, frame, expected });
  }
  assert.ok(byRequest.size > 0, `no valid sample frames in ${samplesDir}`);

  let decoder = null;
  for (const [id, list] of byRequest) {
    const names = list.map((x) => x.name).join(', ');
    const count = list[0].frame.header.chunk_count;
    if (list.length !== count) {
      t.diagnostic(`request ${id} (${names}): ${list.length} of ${count} chunks are samples; not joined`);
      continue;
    }
    const assembler = new ChunkAssembler(id);
    for (const { frame } of [...list].reverse()) assembler.add(frame); // any arrival order
    const payload = assembler.result();
    assert.equal(payload.byteLength, list[0].frame.header.total, `request ${id}: total`);

    for (const { name, expected } of list) {
      if (expected.payload_sha256 !== undefined) assert.equal(sha256(payload), expected.payload_sha256, `${name}: payload_sha256`);
      if (expected.payload_file !== undefined) {
        const file = fs.readFileSync(path.join(samplesDir, expected.payload_file));
        assert.ok(Buffer.from(payload).equals(file), `${name}: the joined chunks differ from ${expected.payload_file}`);
      }
    }
    const counts = list.find(({ expected }) => expected.vertices !== undefined || expected.faces !== undefined);
    if (counts && list[0].frame.header.kind === 1) {
      decoder ??= await draco3d.createDecoderModule({});
      const mesh = decodeDraco(decoder, payload);
      if (counts.expected.vertices !== undefined) assert.equal(mesh.vertices, counts.expected.vertices, `request ${id}: vertices`);
      if (counts.expected.faces !== undefined) assert.equal(mesh.faces, counts.expected.faces, `request ${id}: faces`);
    }
  }
});

// The same calls as src/viewer/draco_worker.ts, on node's build of draco3d.
function decodeDraco(draco, payload) {
  const data = new Int8Array(payload.buffer, payload.byteOffset, payload.byteLength);
  const decoder = new draco.Decoder();
  const mesh = new draco.Mesh();
  try {
    assert.equal(decoder.GetEncodedGeometryType(data), draco.TRIANGULAR_MESH, 'the payload is a Draco triangle mesh');
    const status = decoder.DecodeArrayToMesh(data, data.byteLength, mesh);
    assert.ok(status.ok(), `Draco: ${status.error_msg()}`);
    assert.ok(decoder.GetAttributeId(mesh, draco.POSITION) >= 0, 'the payload has positions');
    return { vertices: mesh.num_points(), faces: mesh.num_faces() };
  } finally {
    draco.destroy(mesh);
    draco.destroy(decoder);
  }
}

test('encodeFrame and decodeFrame round-trip every field', () => {
  const payload = new Uint8Array([1, 2, 3, 4, 5]);
  const fields = { kind: 1, request_id: 0xfedcba98, chunk_index: 2, chunk_count: 3, total: 2 ** 40 + 7 };
  const bytes = encodeFrame(fields, payload);
  assert.equal(bytes.byteLength, 32 + 5);
  assert.deepEqual(Buffer.from(bytes.subarray(0, 4)).toString('latin1'), 'CGVF');
  const { header, payload: out } = decodeFrame(bytes);
  assert.deepEqual(header, { magic: 'CGVF', version: 1, header_bytes: 32, ...fields });
  assert.deepEqual([...out], [1, 2, 3, 4, 5]);
});

test('the header is read little-endian at the offsets of API.md', () => {
  const b = Buffer.alloc(40);
  b.write('CGVF', 0, 'latin1');
  b.writeUInt16LE(1, 4);
  b.writeUInt16LE(1, 6);
  b.writeUInt32LE(77, 8);
  b.writeUInt32LE(0, 12);
  b.writeUInt32LE(1, 16);
  b.writeUInt32LE(32, 20);
  b.writeBigUInt64LE(8n, 24);
  // A DataView over a Buffer's pooled ArrayBuffer: byteOffset must be honoured.
  const h = decodeFrameHeader(b);
  assert.deepEqual(h, {
    magic: 'CGVF',
    version: 1,
    kind: 1,
    request_id: 77,
    chunk_index: 0,
    chunk_count: 1,
    header_bytes: 32,
    total: 8,
  });
  assert.equal(decodeFrame(b.buffer.slice(b.byteOffset, b.byteOffset + b.length)).payload.byteLength, 8);
});

test('malformed headers are rejected with a FrameError naming the problem', () => {
  const good = () => Buffer.from(encodeFrame({ kind: 1, request_id: 1, chunk_index: 0, chunk_count: 1, total: 4 }, new Uint8Array(4)));
  const cases = [
    ['short', (b) => b.subarray(0, 31), /shorter than the 32-byte header/],
    ['magic', (b) => (b.write('CGVX', 0, 'latin1'), b), /bad magic/],
    ['version', (b) => (b.writeUInt16LE(2, 4), b), /version 2/],
    ['header_bytes small', (b) => (b.writeUInt32LE(16, 20), b), /header_bytes 16/],
    ['header_bytes past end', (b) => (b.writeUInt32LE(64, 20), b), /beyond the frame/],
    ['chunk_count 0', (b) => (b.writeUInt32LE(0, 16), b), /chunk_count is 0/],
    ['chunk_index', (b) => (b.writeUInt32LE(1, 12), b), /chunk_index 1 is not below chunk_count 1/],
    ['total huge', (b) => (b.writeBigUInt64LE(2n ** 60n, 24), b), /too large/],
    ['chunk larger than total', (b) => (b.writeBigUInt64LE(2n, 24), b), /larger than the total/],
  ];
  for (const [name, corrupt, message] of cases) {
    assert.throws(
      () => decodeFrame(corrupt(good())),
      (e) => e instanceof FrameError && message.test(e.message),
      name,
    );
  }
});

test('ChunkAssembler joins chunks in chunk_index order whatever their arrival order', () => {
  const whole = new Uint8Array(10).map((_, i) => i * 7);
  const parts = [whole.subarray(0, 4), whole.subarray(4, 8), whole.subarray(8)];
  const frames3 = parts.map((p, i) => decodeFrame(encodeFrame({ kind: 1, request_id: 9, chunk_index: i, chunk_count: 3, total: 10 }, p)));
  const a = new ChunkAssembler(9);
  assert.equal(a.total, null);
  assert.equal(a.add(frames3[2]), false);
  assert.equal(a.total, 10);
  assert.equal(a.add(frames3[0]), false);
  assert.throws(() => a.result(), /incomplete: 2 of 3/);
  assert.equal(a.add(frames3[1]), true);
  assert.equal(a.bytesReceived, 10);
  assert.deepEqual([...a.result()], [...whole]);
});

test('ChunkAssembler rejects duplicates, strangers and disagreeing chunks', () => {
  const f = (fields, n = 2) => decodeFrame(encodeFrame({ kind: 1, request_id: 5, chunk_index: 0, chunk_count: 2, total: 4, ...fields }, new Uint8Array(n)));
  const a = new ChunkAssembler(5);
  a.add(f({}));
  assert.throws(() => a.add(f({})), /received twice/);
  assert.throws(() => a.add(f({ request_id: 6, chunk_index: 1 })), /request 6/);
  assert.throws(() => a.add(f({ chunk_index: 1, total: 5 })), /earlier chunks said/);
  assert.throws(() => a.add(f({ chunk_index: 1 }, 3)), /more than the total/);
  const b = new ChunkAssembler(5);
  b.add(f({}, 1));
  b.add(f({ chunk_index: 1 }, 1));
  assert.throws(() => b.result(), /add up to 2 bytes, the header says 4/);
});
