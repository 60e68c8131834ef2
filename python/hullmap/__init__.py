"""hullmap from Python: SLAM map points to an octree, DBSCAN clusters, convex obstacles and path checks.

The functions and classes are hullmap's C++ library (the extension hullmap._hullmap), with numpy
arrays in and out; docs/PYTHON.md describes them. Everything is in the z-up map frame, map units.
"""
from ._hullmap import (  # noqa: F401
    BuildWarning,
    ConvexHull,
    Error,
    Footprint,
    Map,
    Obstacle,
    ObstaclePart,
    PathCheck,
    Plan,
    Surface,
    Voxels,
    __version__,
    build,
    cluster_colour,
    dbscan,
    load,
    read_points,
)

# The classes and named tuples are hullmap's, whatever module of the package defines them.
for _type in (BuildWarning, ConvexHull, Error, Footprint, Map, Obstacle, ObstaclePart, PathCheck, Plan, Surface,
              Voxels):
    _type.__module__ = __name__
del _type

__all__ = ["BuildWarning", "ConvexHull", "Error", "Footprint", "Map", "Obstacle", "ObstaclePart", "PathCheck",
           "Plan", "Surface", "Voxels", "build", "cluster_colour", "dbscan", "load", "read_points"]


def _to_open3d(self):
    """Open3D geometry of the map: (meshes, voxel_grid).

    meshes: one open3d.geometry.TriangleMesh per convex part (per obstacle when it has none), in
    the obstacle's colour (cluster_colour, as hullmap's pictures); voxel_grid: an
    open3d.geometry.VoxelGrid of the occupied voxels, coloured by label (noise and floor black).
    Needs open3d (Debian's python3-open3d); raises ImportError without it.
    """
    import numpy as np
    import open3d as o3d

    meshes = []
    for obstacle in self.obstacles:
        colour = np.array(cluster_colour(obstacle.id), dtype=np.float64) / 255.0
        for shape in obstacle.parts or [obstacle]:
            # Open3D copies what it is given, and takes only writeable arrays: copies of the views.
            mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(shape.hull.vertices.copy()),
                                             o3d.utility.Vector3iVector(shape.hull.triangles.copy()))
            mesh.paint_uniform_color(colour)
            mesh.compute_vertex_normals()
            meshes.append(mesh)

    voxels = self.voxels
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(voxels.centers.copy()))
    palette = {label: cluster_colour(label) for label in np.unique(voxels.labels).tolist()}
    colours = np.array([palette[label] for label in voxels.labels.tolist()], dtype=np.float64).reshape(-1, 3) / 255.0
    cloud.colors = o3d.utility.Vector3dVector(colours)
    half = self.resolution / 2.0
    if len(voxels.centers):
        low, high = voxels.centers.min(axis=0) - half, voxels.centers.max(axis=0) + half
    else:
        low, high = np.zeros(3), np.full(3, self.resolution)
    # Bounds on the voxel lattice, so that each centre falls in the middle of its own grid cell.
    grid = o3d.geometry.VoxelGrid.create_from_point_cloud_within_bounds(cloud, self.resolution, low, high)
    return meshes, grid


Map.to_open3d = _to_open3d
