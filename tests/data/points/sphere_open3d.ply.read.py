import json, sys, open3d as o3d
pc = o3d.io.read_point_cloud(sys.argv[1], format=sys.argv[2])
print(json.dumps({'points': pc.points, 'normals': pc.normals, 'colors': pc.colors}, default=lambda v: [list(x) for x in v]))
