// End-to-end test of textured meshes, against the real
// server and a real browser: an OBJ, its MTL and a PNG chosen together in
// the file picker go up as one zip; seen face-on, the quad shows the
// texture's four colours in the right quadrants (the PNG is drawn by the
// page's own canvas, an independent reference); the checkerboard mode shows
// alternating dark and light squares; a missing image leaves the mesh
// untextured with a warning; three quads of one OBJ with three materials (a
// red texture, a green Kd, a blue texture) show their own colours, also in
// the flat, toon and smooth display modes; assimp's spider (OBJ + MTL +
// JPEGs, Debian's assimp-testmodels) is drawn with its four materials'
// textures and shows its leg texture's colour; a PLY with UVs
// (Blender's cube_uv.ply) gets the checkerboard, and an OBJ whose UVs are
// all one point does not (the panel says why); a .gltf chosen with its .bin
// and PNG goes up as one upload and shows the same quadrants.  Screenshots go to
// build/test-artifacts/e2e-texture-*.png.
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server),
// CHROMIUM (default /usr/bin/chromium).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { artifactsDir, pngPixels, useViewer } from './harness.mjs';

const assimp = '/usr/share/assimp/models';
const v = useViewer({ tmpPrefix: 'cgview-e2e-texture-', httpErrors: false });

// The viewer's camera looks from (0.55, 0.35, 1) with +y up (Viewer.fitToView):
// the point at (sx, sy) of the plane facing it, sx along the screen's right and sy along its up.
function faceOnCorner(sx, sy) {
  const norm = (a) => a.map((x) => x / Math.hypot(...a));
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const z = norm([0.55, 0.35, 1]);
  const x = norm(cross([0, 1, 0], z));
  const y = cross(z, x);
  return [0, 1, 2].map((i) => sx * x[i] + sy * y[i]).join(' ');
}

// A unit quad facing the camera, its u along the screen's right and v along
// its up (or all its UVs at `uv`); with no `mtl`, it names no material at all (no mtllib, no usemtl).
function faceOnQuadObj(mtl, uv = null) {
  const corner = faceOnCorner;
  return [
    mtl ? `mtllib ${mtl}` : '',
    `v ${corner(-1, -1)}`,
    `v ${corner(1, -1)}`,
    `v ${corner(1, 1)}`,
    `v ${corner(-1, 1)}`,
    ...(uv ? Array(4).fill(`vt ${uv}`) : ['vt 0 0', 'vt 1 0', 'vt 1 1', 'vt 0 1']),
    mtl ? 'usemtl quad' : '',
    'f 1/1 2/2 3/3',
    'f 1/1 3/3 4/4',
    '',
  ].join('\n');
}
const QUAD_MTL = 'newmtl quad\nKd 1 1 1\nmap_Kd quad.png\n';
// The image's rows top to bottom; OBJ's v = 0 is its bottom row.
const TEXELS = { topLeft: [255, 0, 0], topRight: [0, 255, 0], bottomLeft: [0, 0, 255], bottomRight: [255, 255, 0] };

function hue([r, g, b]) {
  const max = Math.max(r, g, b);
  const min = Math.min(r, g, b);
  if (max === min) return null;
  let h;
  if (max === r) h = (60 * (g - b)) / (max - min);
  else if (max === g) h = 120 + (60 * (b - r)) / (max - min);
  else h = 240 + (60 * (r - g)) / (max - min);
  return (h + 360) % 360;
}
const hueDistance = (a, b) => Math.min(Math.abs(a - b), 360 - Math.abs(a - b));
const luminance = ([r, g, b]) => 0.2126 * r + 0.7152 * g + 0.0722 * b;

async function canvasPixels(name) {
  const png = await v.page.locator('#viewport canvas').screenshot();
  fs.writeFileSync(path.join(artifactsDir, `e2e-texture-${name}.png`), png);
  return pngPixels(v.page, png);
}

// The mean colour of a 7×7 patch at (fx, fy) of the way from the canvas's centre
// to its smaller half-side (+y down).
function sample(img, fx, fy) {
  const half = Math.min(img.width, img.height) / 2;
  const cx = Math.round(img.width / 2 + fx * half);
  const cy = Math.round(img.height / 2 + fy * half);
  const sum = [0, 0, 0];
  for (let dy = -3; dy <= 3; ++dy)
    for (let dx = -3; dx <= 3; ++dx) {
      const i = ((cy + dy) * img.width + (cx + dx)) * 4;
      for (let c = 0; c < 3; ++c) sum[c] += img.data[i + c];
    }
  return sum.map((s) => s / 49);
}
const QUADRANTS = { topLeft: [-0.25, -0.25], topRight: [0.25, -0.25], bottomLeft: [-0.25, 0.25], bottomRight: [0.25, 0.25] };

// A PNG of the 2×2 texels, made by the page's canvas (not by CGView).
async function quadPng(texels = TEXELS) {
  const b64 = await v.page.evaluate((texels) => {
    const c = document.createElement('canvas');
    c.width = c.height = 2;
    const g = c.getContext('2d');
    const put = (x, y, [r, gg, b]) => {
      g.fillStyle = `rgb(${r},${gg},${b})`;
      g.fillRect(x, y, 1, 1);
    };
    put(0, 0, texels.topLeft);
    put(1, 0, texels.topRight);
    put(0, 1, texels.bottomLeft);
    put(1, 1, texels.bottomRight);
    return c.toDataURL('image/png').split(',')[1];
  }, texels);
  return Buffer.from(b64, 'base64');
}

// Chooses files in the upload picker; resolves with the mesh shown after it.
async function pick(files, mode) {
  const before = await v.page.evaluate(() => window.__cgview.lastLoaded?.id ?? null);
  await v.page.setInputFiles('#file-input', files);
  await v.page
    .waitForFunction(
      ([prev, m]) => {
        const h = window.__cgview;
        return h.lastLoaded && h.lastLoaded.id !== prev && (m === null ? true : h.texture?.meshId === h.lastLoaded.id && h.texture.mode === m);
      },
      [before, mode],
      { timeout: 60000 },
    )
    .catch((e) => {
      throw new Error(`the upload was not shown (${mode}): ${e.message}${v.describeProblems()}\n${v.server.log()}`);
    });
  const id = await v.page.evaluate(() => window.__cgview.lastLoaded.id);
  return (await fetch(`${v.server.url}/api/v1/meshes/${id}`)).json();
}

const file = (name, text) => ({ name, mimeType: 'application/octet-stream', buffer: Buffer.from(text) });

test('an OBJ, its MTL and a PNG chosen together show the texture face-on, and the checkerboard alternates', async () => {
  const png = await quadPng();
  const mesh = await pick([file('quad.obj', faceOnQuadObj('quad.mtl')), file('quad.mtl', QUAD_MTL), { name: 'quad.png', mimeType: 'image/png', buffer: png }], 'texture');
  assert.equal(mesh.name, 'quad.obj');
  assert.equal(mesh.has_uvs, true);
  assert.equal(mesh.textures.length, 1);
  assert.deepEqual([mesh.textures[0].name, mesh.textures[0].mime, mesh.textures[0].bytes], ['quad.png', 'image/png', png.length]);
  const served = Buffer.from(await (await fetch(`${v.server.url}/api/v1/meshes/${mesh.id}/textures/0`)).arrayBuffer());
  assert.ok(served.equals(png), 'the stored texture is the uploaded PNG');
  assert.equal(await v.page.locator('#texture-panel').isVisible(), true, 'the texture panel shows for a mesh with UVs');

  const img = await canvasPixels('quad');
  for (const [where, [fx, fy]] of Object.entries(QUADRANTS)) {
    const got = sample(img, fx, fy);
    const want = TEXELS[where];
    const h = hue(got);
    assert.ok(h !== null && hueDistance(h, hue(want)) <= 20, `${where}: hue of ${got.map(Math.round)} is not that of ${want}`);
    const max = Math.max(...got);
    assert.ok(max > 60 && max - Math.min(...got) > 0.5 * max, `${where}: ${got.map(Math.round)} is not a saturated colour`);
  }

  // The shaded display modes replace the material but keep the texture; wireframe draws the plain colour.
  for (const mode of ['flat', 'toon', 'hidden-line', 'wireframe']) {
    await v.page.selectOption('#display-mode', mode);
    await v.page.waitForFunction((m) => window.__cgview.display?.mode === m, mode, { timeout: 10000 });
    const shaded = await canvasPixels(`quad-${mode}`);
    const hues = Object.entries(QUADRANTS).map(([where, [fx, fy]]) => [where, sample(shaded, fx, fy)]);
    if (mode === 'wireframe') {
      const textured = hues.filter(([where, got]) => hue(got) !== null && hueDistance(hue(got), hue(TEXELS[where])) <= 20 && Math.max(...got) > 60);
      assert.ok(textured.length < 4, `wireframe draws no texture: ${JSON.stringify(hues)}`);
      continue;
    }
    for (const [where, got] of hues) {
      const h = hue(got);
      // Toon's few bands of light shift the hues a little more.
      assert.ok(
        h !== null && hueDistance(h, hue(TEXELS[where])) <= (mode === 'toon' ? 30 : 20),
        `${mode}, ${where}: hue of ${got.map(Math.round)} is not that of ${TEXELS[where]}`,
      );
    }
  }
  await v.page.selectOption('#display-mode', 'smooth');
  await v.page.waitForFunction(() => window.__cgview.display?.mode === 'smooth', null, { timeout: 10000 });

  await v.page.selectOption('#texture-mode', 'checkerboard');
  await v.page.locator('#texture-squares').fill('2');
  // The value beside the slider follows it.
  assert.equal(
    await v.page
      .locator('label', { has: v.page.getByRole('slider', { name: 'Squares', exact: true }) })
      .locator('.slider-value')
      .innerText(),
    '2',
  );
  await v.page.waitForFunction(() => window.__cgview.texture?.mode === 'checkerboard' && window.__cgview.texture.squares === 2, null, { timeout: 10000 });
  const checker = await canvasPixels('checkerboard');
  const lum = Object.fromEntries(Object.entries(QUADRANTS).map(([k, [fx, fy]]) => [k, luminance(sample(checker, fx, fy))]));
  const light = Math.min(lum.topLeft, lum.bottomRight);
  const dark = Math.max(lum.topRight, lum.bottomLeft);
  assert.ok(light > 2 * dark + 20, `squares alternate dark and light: ${JSON.stringify(lum)}`);
  for (const [k, [fx, fy]] of Object.entries(QUADRANTS)) {
    const c = sample(checker, fx, fy);
    assert.ok(Math.max(...c) - Math.min(...c) < 40, `${k}: the checkerboard is grey, got ${c.map(Math.round)}`);
  }

  await v.page.selectOption('#texture-mode', 'off');
  await v.page.waitForFunction(() => window.__cgview.texture?.mode === 'off', null, { timeout: 10000 });
  const off = await canvasPixels('off');
  const c = sample(off, QUADRANTS.topRight[0], QUADRANTS.topRight[1]);
  assert.ok(Math.max(...c) - Math.min(...c) < 40, `untextured, the quad shows its white Kd: ${c.map(Math.round)}`);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

// Three unit quads side by side facing the camera, one material each: a red
// texture, a green Kd without a map, a blue texture.
const STRIP = [
  ['red', [255, 0, 0]],
  ['green', [0, 255, 0]],
  ['blue', [0, 0, 255]],
];
function stripObj() {
  const lines = ['mtllib strip.mtl', 'vt 0 0', 'vt 1 0', 'vt 1 1', 'vt 0 1'];
  STRIP.forEach(([name], i) => {
    const x0 = i - 1.5;
    lines.push(`v ${faceOnCorner(x0, -0.5)}`, `v ${faceOnCorner(x0 + 1, -0.5)}`, `v ${faceOnCorner(x0 + 1, 0.5)}`, `v ${faceOnCorner(x0, 0.5)}`);
    const v = 4 * i;
    lines.push(`usemtl ${name}`, `f ${v + 1}/1 ${v + 2}/2 ${v + 3}/3 ${v + 4}/4`);
  });
  return lines.join('\n') + '\n';
}
const STRIP_MTL = 'newmtl red\nKd 1 1 1\nmap_Kd red.png\nnewmtl green\nKd 0 1 0\nnewmtl blue\nKd 1 1 1\nmap_Kd blue.png\n';

// The mean colours at the middles of the strip's three quads: found along the
// canvas's middle row as the thirds of the span that is not background.
function stripColours(img) {
  const y = Math.round(img.height / 2);
  const lit = (x) => {
    const i = (y * img.width + x) * 4;
    const px = [img.data[i], img.data[i + 1], img.data[i + 2]];
    return Math.abs(px[0] - 0x1b) + Math.abs(px[1] - 0x1d) + Math.abs(px[2] - 0x22) > 30;
  };
  let left = 0;
  while (left < img.width && !lit(left)) ++left;
  let right = img.width - 1;
  while (right > left && !lit(right)) --right;
  assert.ok(right - left > img.width / 4, `the strip spans ${left}..${right} of ${img.width} pixels`);
  const half = Math.min(img.width, img.height) / 2;
  return [1, 3, 5].map((k) => sample(img, (left + ((right - left) * k) / 6 - img.width / 2) / half, 0));
}

function assertStrip(img, what, tolerance = 20) {
  stripColours(img).forEach((got, i) => {
    const [name, want] = STRIP[i];
    const h = hue(got);
    assert.ok(h !== null && hueDistance(h, hue(want)) <= tolerance && Math.max(...got) > 60, `${what}: the ${name} quad shows ${got.map(Math.round)}`);
  });
}

test('several materials on one mesh: each quad shows its own texture or colour, in the display modes too, and its Kd with textures off', async () => {
  const red = await quadPng({ topLeft: STRIP[0][1], topRight: STRIP[0][1], bottomLeft: STRIP[0][1], bottomRight: STRIP[0][1] });
  const blue = await quadPng({ topLeft: STRIP[2][1], topRight: STRIP[2][1], bottomLeft: STRIP[2][1], bottomRight: STRIP[2][1] });
  const mesh = await pick(
    [
      file('strip.obj', stripObj()),
      file('strip.mtl', STRIP_MTL),
      { name: 'red.png', mimeType: 'image/png', buffer: red },
      { name: 'blue.png', mimeType: 'image/png', buffer: blue },
    ],
    'texture',
  );
  assert.deepEqual(
    mesh.materials.map((m) => [m.name, m.faces, m.texture === null ? null : mesh.textures[m.texture].name]),
    [
      ['red', 2, 'red.png'],
      ['green', 2, null],
      ['blue', 2, 'blue.png'],
    ],
  );
  assert.ok(!mesh.warnings.some((w) => /textur|material/.test(w)), JSON.stringify(mesh.warnings));
  await v.page.waitForFunction(() => window.__cgview.texture?.materials === 3, null, { timeout: 10000 });
  assertStrip(await canvasPixels('strip'), 'texture');

  for (const mode of ['flat', 'toon', 'smooth']) {
    await v.page.selectOption('#display-mode', mode);
    await v.page.waitForFunction((m) => window.__cgview.display?.mode === m, mode, { timeout: 10000 });
    assertStrip(await canvasPixels(`strip-${mode}`), mode, mode === 'toon' ? 30 : 20);
  }

  // The checkerboard replaces every material's look.
  await v.page.selectOption('#texture-mode', 'checkerboard');
  await v.page.waitForFunction(() => window.__cgview.texture?.mode === 'checkerboard', null, { timeout: 10000 });
  assert.equal(await v.page.evaluate(() => window.__cgview.texture.materials), 1);
  for (const c of stripColours(await canvasPixels('strip-checkerboard'))) assert.ok(Math.max(...c) - Math.min(...c) < 40, `the checkerboard is grey, got ${c.map(Math.round)}`);

  // Textures off: each material shows its Kd (white, green, white).
  await v.page.selectOption('#texture-mode', 'off');
  await v.page.waitForFunction(() => window.__cgview.texture?.mode === 'off', null, { timeout: 10000 });
  assert.equal(await v.page.evaluate(() => window.__cgview.texture.materials), 3);
  const [left, middle, right] = stripColours(await canvasPixels('strip-off'));
  for (const c of [left, right]) assert.ok(Math.max(...c) - Math.min(...c) < 40 && Math.max(...c) > 100, `a white Kd, got ${c.map(Math.round)}`);
  assert.ok(hue(middle) !== null && hueDistance(hue(middle), 120) <= 20, `the green Kd, got ${middle.map(Math.round)}`);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('a missing texture image: the mesh shows untextured, with a warning in the page', async () => {
  const mesh = await pick([file('bare.obj', faceOnQuadObj('bare.mtl')), file('bare.mtl', QUAD_MTL)], 'checkerboard');
  assert.equal(mesh.textures.length, 0);
  assert.ok(
    mesh.warnings.some((w) => w.includes("'quad.png' is not in the upload")),
    JSON.stringify(mesh.warnings),
  );
  await v.page.locator('#messages', { hasText: "'quad.png' is not in the upload" }).waitFor({ timeout: 10000 });
  assert.equal(await v.page.locator('#texture-mode option[value="texture"]').isDisabled(), true);
});

test('an OBJ naming no material, chosen with one MTL and its PNG, shows the texture and says what it took', async () => {
  const png = await quadPng();
  const mesh = await pick([file('plain.obj', faceOnQuadObj(null)), file('quad.mtl', QUAD_MTL), { name: 'quad.png', mimeType: 'image/png', buffer: png }], 'texture');
  assert.equal(mesh.textures.length, 1, JSON.stringify(mesh));
  const img = await canvasPixels('no-material');
  for (const [where, [fx, fy]] of Object.entries(QUADRANTS)) {
    const got = sample(img, fx, fy);
    assert.ok(hue(got) !== null && hueDistance(hue(got), hue(TEXELS[where])) <= 20, `${where}: hue of ${got.map(Math.round)} is not that of ${TEXELS[where]}`);
  }
  await v.page.locator('#messages', { hasText: "the upload's only one, 'quad.mtl', is used" }).waitFor({ timeout: 10000 });
});

test("assimp's spider (OBJ, MTL, JPEGs) shows its texture's colour", async () => {
  const dir = path.join(assimp, 'OBJ');
  const names = ['spider.obj', 'spider.mtl', ...fs.readdirSync(dir).filter((n) => n.endsWith('.jpg'))];
  const mesh = await pick(
    names.map((n) => path.join(dir, n)),
    'texture',
  );
  assert.equal(mesh.textures[0].name, 'drkwood2.jpg', 'the texture of the material on most faces');
  // Every material on its faces gets its own texture (the MTL's fifth, Brusttex, is on no face).
  assert.deepEqual(mesh.materials.map((m) => mesh.textures[m.texture].name).sort(), ['SpiderTex.jpg', 'drkwood2.jpg', 'engineflare1.jpg', 'wal67ar_small.jpg']);
  await v.page.waitForFunction(() => window.__cgview.texture?.materials === 4, null, { timeout: 10000 });
  // The reference: the JPEG's mean colour as the page's own decoder reads it.
  const jpeg = fs.readFileSync(path.join(dir, 'drkwood2.jpg')).toString('base64');
  const mean = await v.page.evaluate(async (b64) => {
    const img = new Image();
    img.src = `data:image/jpeg;base64,${b64}`;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.naturalWidth;
    c.height = img.naturalHeight;
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    const { data } = g.getImageData(0, 0, c.width, c.height);
    const s = [0, 0, 0];
    for (let i = 0; i < data.length; i += 4) for (let k = 0; k < 3; ++k) s[k] += data[i + k];
    return s.map((x) => (x * 4) / data.length);
  }, jpeg);
  const want = hue(mean);
  const share = (img) => {
    let near = 0,
      lit = 0;
    for (let i = 0; i < img.data.length; i += 4) {
      const px = [img.data[i], img.data[i + 1], img.data[i + 2]];
      const max = Math.max(...px);
      const min = Math.min(...px);
      if (max < 30 || (px[0] === 0x1b && px[1] === 0x1d && px[2] === 0x22)) continue; // the background
      ++lit;
      if (max - min > 0.15 * max && hueDistance(hue(px), want) <= 20) ++near;
    }
    return lit ? near / lit : 0;
  };
  const textured = share(await canvasPixels('spider'));
  await v.page.selectOption('#texture-mode', 'off');
  await v.page.waitForFunction(() => window.__cgview.texture?.mode === 'off', null, { timeout: 10000 });
  const plain = share(await canvasPixels('spider-off'));
  assert.ok(
    textured > 0.3 && textured > plain + 0.2,
    `the texture's hue (${Math.round(want)}°) covers ${(100 * textured).toFixed(1)}% of the spider, ${(100 * plain).toFixed(1)}% untextured`,
  );
});

test("a PLY with UVs (Blender's cube_uv.ply) gets the checkerboard", async () => {
  const mesh = await pick([path.join(assimp, 'PLY', 'cube_uv.ply')], 'checkerboard');
  assert.equal(mesh.has_uvs, true);
  assert.deepEqual(mesh.textures, []);
  assert.equal(await v.page.locator('#texture-panel').isVisible(), true);
});

test('an OBJ whose UVs are all one point shows its plain surface, not the checkerboard, and says why', async () => {
  const mesh = await pick([file('one-point-uv.obj', faceOnQuadObj(null, '0.5 0.5'))], 'off');
  assert.equal(mesh.has_uvs, true);
  assert.match(await v.page.locator('#texture-note').innerText(), /all the same point: nothing to show/);
  assert.match(await v.page.evaluate(() => window.__cgview.texture.uvProblem), /all the same point/);
  // The checkerboard is still there to choose.
  await v.page.selectOption('#texture-mode', 'checkerboard');
  await v.page.waitForFunction(() => window.__cgview.texture?.mode === 'checkerboard', null, { timeout: 10000 });
});

// The face-on quad as glTF ships it: the .gltf names its buffer in a .bin and
// its image in a PNG beside it (glTF's v runs down the image, OBJ's up).
function faceOnQuadGltf() {
  const corners = [
    [-1, -1],
    [1, -1],
    [1, 1],
    [-1, 1],
  ].map(([sx, sy]) => faceOnCorner(sx, sy).split(' ').map(Number));
  const bin = Buffer.alloc(92);
  corners.flat().forEach((x, i) => bin.writeFloatLE(x, 4 * i));
  [0, 1, 1, 1, 1, 0, 0, 0].forEach((x, i) => bin.writeFloatLE(x, 48 + 4 * i));
  [0, 1, 2, 0, 2, 3].forEach((x, i) => bin.writeUInt16LE(x, 80 + 2 * i));
  const lo = [0, 1, 2].map((k) => Math.min(...corners.map((c) => c[k])));
  const hi = [0, 1, 2].map((k) => Math.max(...corners.map((c) => c[k])));
  const gltf = {
    asset: { version: '2.0' },
    scene: 0,
    scenes: [{ nodes: [0] }],
    nodes: [{ mesh: 0 }],
    meshes: [{ primitives: [{ attributes: { POSITION: 0, TEXCOORD_0: 1 }, indices: 2, material: 0 }] }],
    materials: [{ pbrMetallicRoughness: { baseColorTexture: { index: 0 } } }],
    textures: [{ source: 0 }],
    images: [{ uri: 'quad%20texture.png' }],
    buffers: [{ uri: 'quad.bin', byteLength: 92 }],
    bufferViews: [
      { buffer: 0, byteOffset: 0, byteLength: 48 },
      { buffer: 0, byteOffset: 48, byteLength: 32 },
      { buffer: 0, byteOffset: 80, byteLength: 12 },
    ],
    accessors: [
      { bufferView: 0, componentType: 5126, count: 4, type: 'VEC3', min: lo, max: hi },
      { bufferView: 1, componentType: 5126, count: 4, type: 'VEC2' },
      { bufferView: 2, componentType: 5123, count: 6, type: 'SCALAR' },
    ],
  };
  return { gltf: JSON.stringify(gltf), bin };
}

test('a .gltf chosen with its .bin and its PNG goes up as one upload and shows the texture face-on', async () => {
  const png = await quadPng();
  const { gltf, bin } = faceOnQuadGltf();
  await v.page.selectOption('#display-mode', 'flat');
  const mesh = await pick(
    [file('quad.gltf', gltf), { name: 'quad.bin', mimeType: 'application/octet-stream', buffer: bin }, { name: 'quad texture.png', mimeType: 'image/png', buffer: png }],
    'texture',
  );
  assert.equal(mesh.name, 'quad.gltf');
  assert.equal(mesh.report.faces, 2);
  assert.equal(mesh.textures.length, 1);
  const served = Buffer.from(await (await fetch(`${v.server.url}/api/v1/meshes/${mesh.id}/textures/0`)).arrayBuffer());
  assert.ok(served.equals(png), 'the stored texture is the PNG chosen beside the .gltf');
  const names = (await (await fetch(`${v.server.url}/api/v1/meshes`)).json()).meshes.map((m) => m.name);
  assert.ok(!names.includes('quad.bin'), `the .bin is not a mesh of its own: ${names}`);
  const img = await canvasPixels('gltf-quad');
  for (const [where, [fx, fy]] of Object.entries(QUADRANTS)) {
    const got = sample(img, fx, fy);
    const h = hue(got);
    assert.ok(h !== null && hueDistance(h, hue(TEXELS[where])) <= 20, `${where}: hue of ${got.map(Math.round)} is not that of ${TEXELS[where]}`);
  }
});
