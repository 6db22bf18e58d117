"""The compiled ray casting of the thickness stage (:mod:`.compiled_rays`, issue 35) gives
libigl's hits to the last bit (face, t, u, v: the same box and triangle tests in the same
order), the same thickness, and the same L from :func:`estimate_lfs`: on a torus and on a
gear's long thin triangles, with rays aimed exactly at vertices and edges, along the axes
and from an open mesh (the parity cannot tell the sides there)."""

from types import SimpleNamespace

import numpy as np
import pytest

from vorobound.geometry.kernels import pure_numpy
from vorobound.sampling.surfaces.cad_meshes import gear
from vorobound.sampling.surfaces.demo_meshes import torus_mesh

pytest.importorskip("numba")
pytestmark = pytest.mark.skipif(pure_numpy(), reason="VOROBOUND_PURE_NUMPY: no compiled rays")


def _meshes():
    return {
        "torus": torus_mesh(3.0, 1.0, 48, 16, jitter=0.2, seed=1),
        "gear": gear(teeth=12, faces=800, bore=2.0),
    }


def _rays(mesh, rng):
    """Rays from points on faces along ± the face normal (tilted), from off the surface at vertices
    and edge midpoints (exactly through them, where two or more faces meet), and along the
    axes (a direction component 0: 1/d is not finite)."""
    points, faces = mesh.points, mesh.triangles
    corners = points[faces]
    face = rng.integers(0, len(faces), 300)
    on = np.einsum("nc,ncd->nd", rng.dirichlet(np.ones(3), len(face)), corners[face])
    normal = np.cross(corners[face, 1] - corners[face, 0], corners[face, 2] - corners[face, 0])
    # tilted: a gear's normals lie along the axes
    normal = normal / np.linalg.norm(normal, axis=1)[:, None] + 0.01 * rng.normal(size=(300, 3))
    targets = np.vstack(
        [
            points[rng.integers(0, len(points), 200)],
            corners[face[:200]][:, :2].mean(axis=1),  # edge midpoints
        ]
    )
    low, high = points.min(axis=0), points.max(axis=0)
    off = rng.uniform(low - 1, high + 1, (len(targets), 3))
    axes = np.repeat(np.eye(3), 20, axis=0) * rng.choice([-1.0, 1.0], (60, 1))
    origins = np.vstack([on, on, off, rng.uniform(low, high, (60, 3))])
    directions = np.vstack([normal, -normal, targets - off, axes])
    return origins, directions / np.linalg.norm(directions, axis=1)[:, None]


@pytest.mark.parametrize("name", ["torus", "gear"])
def test_compiled_hits_are_libigls_bit_for_bit(name):
    from vorobound.sampling.lfs.thickness import RayCaster

    mesh = _meshes()[name]
    caster = RayCaster(mesh.points, mesh.triangles)
    origins, directions = _rays(mesh, np.random.default_rng(0))
    # The rays as given (no tilt): the hits of rays not flagged are libigl's, as a set.
    ray, face, t, uv, flagged = caster._ray_tree().cast(origins, directions)
    plain = caster._libigl_hits(origins, directions)
    assert flagged[-60:].all()  # along an axis
    assert flagged[:-60].any()  # equal t: through an edge or a vertex
    assert not flagged[:600].all()
    keep = ~flagged[plain.ray]
    ours = np.c_[ray, face, t, uv]
    theirs = np.c_[plain.ray[keep], plain.face[keep], plain.t[keep], plain.uv[keep]]
    assert len(ours) > 1000
    assert np.array_equal(ours[np.lexsort(ours.T[::-1])], theirs[np.lexsort(theirs.T[::-1])])
    # Within a ray the hits are sorted by t (libigl's order for equal t: its rays again).
    assert (np.diff(t)[np.diff(ray) == 0] > 0).all()
    # RayCaster.hits (tilted rays): the whole answer, order included, is libigl's.
    tilted = caster.hits(origins, directions)
    from vorobound.sampling.lfs.thickness import _tilted

    again = caster._libigl_hits(origins, _tilted(origins, directions))
    for field in ("ray", "face", "t", "uv"):
        assert np.array_equal(getattr(tilted, field), getattr(again, field)), field


def _thickness_both(monkeypatch, mesh, origins, normals, face, lift):
    from vorobound.sampling.lfs import thickness as module

    group = np.arange(len(mesh.triangles)) % 3
    allowed = np.ones((3, 3), dtype=bool)
    allowed[0, 1] = allowed[1, 0] = False
    args = (origins, normals, face, allowed, group, group[face], lift)
    near = np.full(len(face), 1e-3)
    compiled = module.thickness(module.RayCaster(mesh.points, mesh.triangles), *args, near)
    monkeypatch.setattr(module, "compiled_rays", lambda: None)
    plain = module.thickness(module.RayCaster(mesh.points, mesh.triangles), *args, near)
    return compiled, plain


@pytest.mark.parametrize("name", ["torus", "gear", "open gear"])
def test_thickness_with_compiled_rays_is_the_same(monkeypatch, name):
    """thickness() reduced per ray in compiled code equals the reduction of libigl's hits:
    lifted hits (a lift that moves the hits on every other face), hits skipped near the
    origin, rays of unknown side (an open mesh)."""
    from vorobound.sampling.lfs import thickness as module

    mesh = _meshes()[name.split()[-1]]
    if name.startswith("open"):
        mesh = SimpleNamespace(points=mesh.points, triangles=mesh.triangles[40:])
    rng = np.random.default_rng(4)
    corners = mesh.points[mesh.triangles]
    face = rng.integers(0, len(corners), 500)
    origins = np.einsum("nc,ncd->nd", rng.dirichlet(np.ones(3), len(face)), corners[face])
    normals = np.cross(corners[face, 1] - corners[face, 0], corners[face, 2] - corners[face, 0])
    normals /= np.linalg.norm(normals, axis=1)[:, None]

    def lift(faces, bary):
        moved = faces % 2 == 1
        lifted = np.einsum("nc,ncd->nd", bary, corners[faces])
        return lifted * np.where(moved, 1.001, 1.0)[:, None], moved

    compiled, plain = _thickness_both(monkeypatch, mesh, origins, normals, face, lift)
    for field in module.FIELDS:
        assert np.array_equal(getattr(compiled, field), getattr(plain, field)), field
    assert np.isfinite(compiled.inward).sum() > 100 and np.isfinite(compiled.outward).any()
    if name.startswith("open"):
        assert (~compiled.inward_known).any()


@pytest.mark.slow
@pytest.mark.parametrize("name", ["torus", "gear"])
def test_lfs_with_compiled_rays_is_the_same_bit_for_bit(monkeypatch, name):
    """estimate_lfs gives the same L to the last bit with the compiled rays and with libigl's
    (a new mesh each time: the estimate is cached on the mesh)."""
    import warnings

    from vorobound.errors import VoroboundWarning
    from vorobound.sampling.lfs import thickness as module
    from vorobound.sampling.lfs.compiled_rays import RayTree
    from vorobound.sampling.lfs.estimate import estimate_lfs

    cast = []
    crossings = RayTree.crossings
    monkeypatch.setattr(RayTree, "crossings", lambda *a: cast.append(1) or crossings(*a))
    values = []
    for compiled in (True, False):
        if not compiled:
            monkeypatch.setattr(module, "compiled_rays", lambda: None)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", VoroboundWarning)
            mesh = {
                "torus": lambda: torus_mesh(3.0, 1.0, 24, 8, jitter=0.2, seed=1),
                "gear": lambda: gear(teeth=12, faces=400, width=3.0, bore=3.0),
            }[name]()
            values.append(estimate_lfs(mesh).lfs)
    assert cast  # the compiled rays ran
    assert np.isfinite(values[0]).all()
    assert np.array_equal(values[0], values[1])
