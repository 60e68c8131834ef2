"""Map.to_open3d: a mesh per convex part, coloured as hullmap's pictures colour its obstacle, and a
voxel grid of the map's occupied voxels. Skipped, saying so, where open3d does not import."""
import numpy as np
import pytest

import hullmap

o3d = pytest.importorskip("open3d", reason="open3d (Debian's python3-open3d) is not installed")


def test_meshes_and_voxel_grid_are_the_maps():
    built = hullmap.build("maps/simple/map_points.txt", up="-y", eps=0.12, min_pts=5, concavity=0.1)
    meshes, grid = built.to_open3d()
    shapes = [(o, s) for o in built.obstacles for s in (o.parts or [o])]
    assert len(meshes) == len(shapes) > len(built.obstacles)
    for mesh, (obstacle, shape) in zip(meshes, shapes):
        np.testing.assert_array_equal(np.asarray(mesh.vertices), shape.hull.vertices)
        np.testing.assert_array_equal(np.asarray(mesh.triangles), shape.hull.triangles)
        assert mesh.is_watertight()
        colour = np.asarray(hullmap.cluster_colour(obstacle.id)) / 255.0
        np.testing.assert_allclose(np.asarray(mesh.vertex_colors), np.tile(colour, (len(mesh.vertices), 1)))
    assert isinstance(grid, o3d.geometry.VoxelGrid) and grid.voxel_size == built.resolution
    voxels = built.voxels
    assert len(grid.get_voxels()) == len(voxels.centers)
    # Each voxel of the grid is centred on a voxel of the map.
    centres = np.array([grid.get_voxel_center_coordinate(v.grid_index) for v in grid.get_voxels()])
    ours = {tuple(np.round(c / built.resolution - 0.5).astype(int)) for c in voxels.centers}
    theirs = {tuple(np.round(c / built.resolution - 0.5).astype(int)) for c in centres}
    assert ours == theirs


def test_cluster_colour_is_the_pictures_palette():
    assert hullmap.cluster_colour(-1) == (0, 0, 0)
    assert len({hullmap.cluster_colour(label) for label in range(40)}) == 40
