"""The README's Python workflow: a CAD-like part from mesh to advice, sample and check, with the
same names as the commands (each result's to_dict() is the command's --json)."""

import os
import tempfile
import warnings

COMMANDS = """\
vorobound advise --mesh cube.stl --rho-f 4 --mode tight
vorobound sample --mesh cube.stl --eps EPS -o cube.npz
vorobound check --balls cube.npz --mesh cube.stl --eps EPS --out check/"""


def run(folder: str) -> list[str]:
    """Write the part, then advise, sample and check it; the lines of the block."""
    import meshio

    import vorobound
    from vorobound.sampling.surfaces.cad_meshes import cube

    part = os.path.join(folder, "cube.stl")
    mesh = cube()  # the 12-triangle cube [-1, 1]³: sharp edges, as a CAD export
    meshio.write(part, meshio.Mesh(mesh.points, [("triangle", mesh.triangles)]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the sharp-edge notice (once per mesh and process)
        advice = vorobound.advise(mesh=part, rho_f=4, mode="tight")
        balls = os.path.join(folder, "cube.npz")
        sample = vorobound.sample(mesh=part, eps=advice.eps, output=balls)
        check = vorobound.check(balls=balls, mesh=part, eps=advice.eps)
    failed = ", ".join(f"{k}: {n}" for k, n in check.failures.items() if n) or "none"
    edges = check.to_dict()["violations_at_features"]
    at_edges = ", ".join(
        f"{k}: {n}" for k, n in edges.items() if k not in ("worst", "n_guide_triangles") and n
    )
    return [
        "```python",
        "import vorobound",
        "",
        'advice = vorobound.advise(mesh="cube.stl", rho_f=4, mode="tight")',
        f"advice.eps, advice.claim  # {advice.eps:.6g}, {advice.claim!r}",
        'sample = vorobound.sample(mesh="cube.stl", eps=advice.eps, output="cube.npz")',
        f"sample.n_samples, sample.coverage_max  # {sample.n_samples:,}, {sample.coverage_max:.3f}",
        'check = vorobound.check(balls="cube.npz", mesh="cube.stl", eps=advice.eps)',
        f"check.n_guide_triangles, check.ok  # {check.n_guide_triangles:,}, {check.ok}",
        f"check.failures  # on smooth patches, nonzero: {failed}",
        'check.to_dict()["violations_at_features"]  # '
        f"{at_edges or 'none'} of {edges['n_guide_triangles']:,} at the sharp edges",
        "check.to_dict()  # what `vorobound check ... --json` prints",
        "```",
        "",
        "The same from the shell (exit code 1 from `check` when something fails):",
        "",
        "```",
        COMMANDS.replace("EPS", f"{advice.eps:.6g}"),
        "```",
    ]


def render() -> str:
    with tempfile.TemporaryDirectory() as folder:
        return "\n".join(run(folder)) + "\n"


def quick_check(block: str) -> None:
    """The advice lines (seconds) recomputed; the sample and check take about a minute."""
    import vorobound

    with tempfile.TemporaryDirectory() as folder, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import meshio

        from vorobound.sampling.surfaces.cad_meshes import cube

        part = os.path.join(folder, "cube.stl")
        mesh = cube()
        meshio.write(part, meshio.Mesh(mesh.points, [("triangle", mesh.triangles)]))
        advice = vorobound.advise(mesh=part, rho_f=4, mode="tight")
    assert f"advice.eps, advice.claim  # {advice.eps:.6g}, {advice.claim!r}" in block
    assert f"--eps {advice.eps:.6g} -o cube.npz" in block


if __name__ == "__main__":
    print(render(), end="")
