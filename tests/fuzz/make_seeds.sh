#!/usr/bin/env bash
# Writes the seed corpora (tests/fuzz/corpus/TARGET/) from real files: small
# sample meshes (CGAL's data, libcgal-demo), Debian's assimp-testmodels, and
# files CGView itself writes (build/bin/cgview convert and run).  Run once
# after a build; the seeds are committed, so CI does not run this.
#
#   tests/fuzz/make_seeds.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")"
BUILD=${1:-../../build}
CGVIEW=$BUILD/bin/cgview
SAMPLES=$BUILD/samples
ASSIMP=/usr/share/assimp/models
C=corpus
# Written over, never removed: the regression-* inputs (findings, fixed) and
# the hand-written params/ and config/ seeds stay.
mkdir -p $C/{off,obj,ply,stl,xyz,gltf,glb,drc,mtl,skeleton,voxel,zip,frame,json,params,config}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Meshes: the small samples, and each written by CGView in every format.
for m in tetrahedron cube_quad pyramid triangular_hole tet-shuffled quad; do cp "$SAMPLES/$m.off" $C/off/; done
cp "$SAMPLES/colored_tetra.ply" $C/ply/ 2>/dev/null || true
for m in tetrahedron cube_quad; do
  "$CGVIEW" convert "$SAMPLES/$m.off" $C/obj/$m.obj >/dev/null
  "$CGVIEW" convert "$SAMPLES/$m.off" $C/ply/$m.ply >/dev/null
  "$CGVIEW" convert "$SAMPLES/$m.off" $C/stl/$m.stl >/dev/null
  "$CGVIEW" convert "$SAMPLES/$m.off" $C/glb/$m.glb >/dev/null
  "$CGVIEW" convert "$SAMPLES/$m.off" $C/drc/$m.drc >/dev/null
done
# Point clouds that Open3D and draco_encoder wrote (tests/data/points); the
# first byte of an xyz seed picks the format (0: XYZ, 1: PTS).
POINTS=../data/points
{ printf '\0'; cat $POINTS/sphere_open3d.xyz; } >$C/xyz/sphere_open3d.xyz
{ printf '\1'; cat $POINTS/sphere_open3d.pts; } >$C/xyz/sphere_open3d.pts
printf '\0# a scan\n0 0 0\n1 2.5 -3e2\n' >$C/xyz/rows.xyz
printf '\1 2\n0 0 0 7\n1 0 0 7\n1\n0 1 0 7\n' >$C/xyz/two_scans.pts
cp $POINTS/sphere_open3d.ply $C/ply/
cp $POINTS/sphere_draco.drc $C/drc/
# Files from other tools (assimp's test models), where small.
small() { find "$@" -type f -size -6k 2>/dev/null | head -12; }
for f in $(small $ASSIMP/OBJ -name '*.obj'); do cp "$f" $C/obj/; done
for f in $(small $ASSIMP/PLY -name '*.ply'); do cp "$f" $C/ply/; done
for f in $(small $ASSIMP/STL -iname '*.stl'); do cp "$f" $C/stl/; done
for f in $(small $ASSIMP/OFF -name '*.off'); do cp "$f" $C/off/; done
for f in $(small $ASSIMP/OBJ -name '*.mtl'); do cp "$f" $C/mtl/; done
for f in $(small $ASSIMP/glTF2 -name '*.gltf'); do grep -q 'data:' "$f" && cp "$f" $C/gltf/ || true; done
for f in $(small $ASSIMP/glTF2 -name '*.glb'); do cp "$f" $C/glb/; done

# Skeletons and voxel grids that CGView writes; the first byte picks the format.
"$CGVIEW" run skeleton_projection "$SAMPLES/tetrahedron.off" -o "$tmp/s.cg" >/dev/null 2>&1 || true
"$CGVIEW" run voxelize "$SAMPLES/tetrahedron.off" --resolution 6 -o "$tmp/v.nrrd" >/dev/null 2>&1 || true
python3 - "$tmp" $C <<'PY'
import json, os, struct, sys, zipfile, io
tmp, c = sys.argv[1], sys.argv[2]
def put(target, name, data):
    open(os.path.join(c, target, name), 'wb').write(data)
# Skeletons: one node path and a branch in each format (skeleton_io.h).
nodes = [(0, 0, 0), (1, 0, 0), (2, 0, 0), (1, 1, 0)]
edges = [(0, 1), (1, 2), (1, 3)]
put('skeleton', 'path.polylines', b'\x00' + b'3 0 0 0 1 0 0 2 0 0\n2 1 0 0 1 1 0\n')
cg = '# D:3 NV:4 NE:3\n' + ''.join('v %g %g %g\n' % n for n in nodes) + ''.join('e %d %d\n' % (a + 1, b + 1) for a, b in edges)
put('skeleton', 'branch.cg', b'\x01' + cg.encode())
obj = ''.join('v %g %g %g\n' % n for n in nodes) + 'l 1 2 3\nl 2 4\n'
put('skeleton', 'branch.obj', b'\x02' + obj.encode())
put('skeleton', 'branch.json', b'\x03' + json.dumps({'nodes': nodes, 'edges': edges, 'radii': [0.1] * 4}).encode())
if os.path.exists(os.path.join(tmp, 's.cg')):
    put('skeleton', 'tetra.cg', b'\x01' + open(os.path.join(tmp, 's.cg'), 'rb').read())
# Voxel grids: a 3x2x2 grid in each format the readers decode.
put('voxel', 'grid.binvox', b'\x00' + b'#binvox 1\ndim 3 2 2\ntranslate 0 0 0\nscale 1\ndata\n' + bytes([0, 5, 1, 7]))
nrrd = b'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 3 2 2\nencoding: raw\nspace origin: (0,0,0)\nspacings: 1 1 1\n\n' + bytes(range(12))
put('voxel', 'grid.nrrd', b'\x01' + nrrd)
if os.path.exists(os.path.join(tmp, 'v.nrrd')):
    put('voxel', 'tetra.nrrd', b'\x01' + open(os.path.join(tmp, 'v.nrrd'), 'rb').read())
vti = ('<?xml version="1.0"?>\n<VTKFile type="ImageData" version="0.1" byte_order="LittleEndian">\n'
       '<ImageData WholeExtent="0 2 0 1 0 1" Origin="0 0 0" Spacing="1 1 1">\n<Piece Extent="0 2 0 1 0 1">\n'
       '<PointData Scalars="v"><DataArray type="UInt8" Name="v" format="ascii">0 1 0 1 1 0 0 0 1 1 1 0</DataArray></PointData>\n'
       '</Piece>\n</ImageData>\n</VTKFile>\n')
put('voxel', 'grid.vti', b'\x02' + vti.encode())
xyzi = struct.pack('<I', 2) + bytes([0, 0, 0, 1, 2, 1, 1, 3])
chunk = lambda tag, content, children=b'': tag + struct.pack('<II', len(content), len(children)) + content + children
vox = b'VOX ' + struct.pack('<I', 150) + chunk(b'MAIN', b'', chunk(b'SIZE', struct.pack('<III', 3, 2, 2)) + chunk(b'XYZI', xyzi))
put('voxel', 'grid.vox', b'\x03' + vox)
# Zips: an OBJ with its MTL and a PNG, a PLY alone, a zip of no mesh.
png = b'\x89PNG\r\n\x1a\n' + struct.pack('>I', 13) + b'IHDR' + struct.pack('>IIBBBBB', 1, 1, 8, 2, 0, 0, 0) + b'\0' * 4
obj = b'mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl a\nf 1/1 2/2 3/3\n'
mtl = b'newmtl a\nKd 1 0 0\nmap_Kd t.png\n'
for name, files in [('textured.zip', {'m.obj': obj, 'm.mtl': mtl, 't.png': png}),
                    ('ply.zip', {'t.ply': open(os.path.join(c, 'ply', 'tetrahedron.ply'), 'rb').read()}),
                    ('nomesh.zip', {'readme.txt': b'no mesh here'})]:
    b = io.BytesIO()
    with zipfile.ZipFile(b, 'w', zipfile.ZIP_DEFLATED) as z:
        for n, d in files.items(): z.writestr(n, d)
    put('zip', name, b.getvalue())
# Frames: the 32-byte header (protocol/frames.h) and a payload.
for kind in (1, 2, 3):
    payload = b'payload-%d' % kind
    h = b'CGVF' + struct.pack('<HHIIIIQ', 1, kind, 7, 0, 1, 32, len(payload))
    put('frame', 'kind%d' % kind, h + payload)
# JSON: a job, a WebSocket message, a share, a config.
for i, doc in enumerate([{'algorithm': 'sdf', 'inputs': {'mesh': 'm1'}, 'params': {'rays': 25, 'cone': 2.0}},
                         {'type': 'get_mesh', 'request_id': 3, 'mesh_id': 'm1', 'lod': 'progressive'},
                         {'users': ['alice'], 'everyone': False},
                         {'server': {'max_upload_mb': 256, 'rate_limit': {'rate': 50, 'burst': 200}}, 'quotas': {'default': {'storage_mb': 500}}}]):
    put('json', 'doc%d.json' % i, json.dumps(doc).encode())
PY
# A text glTF with a data: URI buffer, a node transform and two primitives.
python3 - $C <<'PY'
import base64, json, struct, sys
pos = struct.pack('<9f', 0, 0, 0, 1, 0, 0, 0, 1, 0)
idx = struct.pack('<3H', 0, 1, 2) + b'\0\0'
buf = pos + idx
doc = {'asset': {'version': '2.0'}, 'scene': 0, 'scenes': [{'nodes': [0]}],
       'nodes': [{'mesh': 0, 'translation': [1, 2, 3], 'children': [1]}, {'mesh': 0, 'scale': [2, 2, 2]}],
       'meshes': [{'primitives': [{'attributes': {'POSITION': 0}, 'indices': 1}, {'attributes': {'POSITION': 0}, 'mode': 5}]}],
       'accessors': [{'bufferView': 0, 'componentType': 5126, 'count': 3, 'type': 'VEC3', 'min': [0, 0, 0], 'max': [1, 1, 0]},
                     {'bufferView': 1, 'componentType': 5123, 'count': 3, 'type': 'SCALAR'}],
       'bufferViews': [{'buffer': 0, 'byteLength': 36}, {'buffer': 0, 'byteOffset': 36, 'byteLength': 6}],
       'buffers': [{'byteLength': len(buf), 'uri': 'data:application/octet-stream;base64,' + base64.b64encode(buf).decode()}]}
open(sys.argv[1] + '/gltf/two_primitives.gltf', 'w').write(json.dumps(doc))
PY
du -sh $C; for d in $C/*; do echo "$(basename $d): $(ls $d | wc -l) files"; done
