#!/usr/bin/env python3
"""The ParaView files of `stiffmsa solve --vtk` read by meshio, an independent reader: a
cantilever's grid, its tip displacement against the result file's deflection, and the .pvd
collection naming its .vtu.

    test_vtk_meshio.py --cli build/stiffmsa --source .

Exits 77 (ctest's "skipped") where meshio is not installed."""
import argparse
import json
import pathlib
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ElementTree

SKIPPED = 77


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--cli", required=True)
    parser.add_argument("--source", required=True, type=pathlib.Path)
    args = parser.parse_args()
    try:
        import meshio
        import numpy
    except ImportError:
        print("skipped: meshio is not installed (Debian python3-meshio; scripts/install-deps.sh viewer)")
        return SKIPPED
    failures = []

    def check(condition, message):
        if not condition:
            failures.append(message)
            print("FAIL:", message)

    with tempfile.TemporaryDirectory() as temporary:
        folder = pathlib.Path(temporary)
        for example, beams in (("cantilever.yaml", 1), ("industrial-6axis.yaml", None)):
            model = args.source / "examples" / example
            grid, result_file = folder / (model.stem + ".vtu"), folder / (model.stem + ".json")
            run = subprocess.run([args.cli, "solve", str(model), "--vtk", str(grid), "--json", str(result_file)],
                                 capture_output=True, text=True)
            check(run.returncode == 0, f"solve {example} --vtk: exit {run.returncode}: {run.stderr}")
            mesh = meshio.read(grid)
            # The result file's link ends by link name, in model order (the grid's `link` index).
            result = {"links": [dict(ends, name=name) for name, ends in
                                json.loads(result_file.read_text())["link_ends"].items()]}
            lines = mesh.cells_dict["line"]
            kinds = numpy.ravel(mesh.cell_data_dict["link_kind"]["line"])
            links = numpy.ravel(mesh.cell_data_dict["link"]["line"])
            check(len(set(links.tolist())) == len(result["links"]), f"{example}: not one cell group per link")
            if beams:
                check(len(lines) == 8 * beams and (kinds == 0).all(), f"{example}: a beam is not 8 lines")
            # Each link's last point is its `to` end: its displacement is the result's.
            displacement = mesh.point_data["displacement"]
            rotation = mesh.point_data["rotation"]
            for k, link in enumerate(result["links"]):
                last_point = lines[links == k][-1][1]
                expected = numpy.array(link["to"]["deflection"])
                scale = max(numpy.abs(expected).max(), 1e-300)
                got = numpy.concatenate([displacement[last_point], rotation[last_point]])
                check(numpy.abs(got - expected).max() <= 1e-12 * scale,
                      f"{example}: link {link['name']}: {got} against {expected}")
            # The end wrenches: the result's, on every piece of the link.
            wrench_to = mesh.cell_data_dict["end_wrench_to"]["line"]
            for k, link in enumerate(result["links"]):
                if link["to"].get("wrench") is not None:
                    expected = numpy.array(link["to"]["wrench"])
                    got = wrench_to[links == k]
                    check(numpy.abs(got - expected).max() <= 1e-12 * max(numpy.abs(expected).max(), 1e-300),
                          f"{example}: link {link['name']}: end wrench {got[0]} against {expected}")

        collection = folder / "arm.pvd"
        run = subprocess.run([args.cli, "solve", str(args.source / "examples/industrial-6axis.yaml"), "--vtk",
                              str(collection)], capture_output=True, text=True)
        check(run.returncode == 0, f"solve --vtk arm.pvd: exit {run.returncode}: {run.stderr}")
        datasets = ElementTree.parse(collection).getroot().findall("./Collection/DataSet")
        check(len(datasets) == 1 and datasets[0].get("file") == "arm-loads.vtu",
              f"the .pvd does not name arm-loads.vtu: {[d.attrib for d in datasets]}")
        check(len(meshio.read(folder / "arm-loads.vtu").points) > 0, "arm-loads.vtu is empty")
        run = subprocess.run([args.cli, "solve", str(args.source / "examples/cantilever.yaml"), "--vtk",
                              str(folder / "out.vtk")], capture_output=True, text=True)
        check(run.returncode == 2 and ".vtu" in run.stderr, f"--vtk out.vtk is not refused: {run.stderr}")

        # Load cases: the .vtu of the top level, one .vtu per case and their collection; each
        # case's grid moves as that case's results say.
        portal = args.source / "examples/portal-frame-load-cases.yaml"
        run = subprocess.run([args.cli, "solve", str(portal), "--vtk", str(folder / "portal.vtu"), "--json",
                              str(folder / "portal.json")], capture_output=True, text=True)
        check(run.returncode == 0, f"solve portal --vtk: exit {run.returncode}: {run.stderr}")
        datasets = ElementTree.parse(folder / "portal.pvd").getroot().findall("./Collection/DataSet")
        names = [d.get("name") for d in datasets]
        check(names == ["loads", "snow", "hoist", "weight"], f"portal.pvd names {names}")
        result = json.loads((folder / "portal.json").read_text())
        for dataset in datasets:
            case = result if dataset.get("name") == "loads" else result["load_cases"][dataset.get("name")]
            mesh = meshio.read(folder / dataset.get("file"))
            lines = mesh.cells_dict["line"]
            links = numpy.ravel(mesh.cell_data_dict["link"]["line"])
            for k, (name, ends) in enumerate(case["link_ends"].items()):
                last_point = lines[links == k][-1][1]
                expected = numpy.array(ends["to"]["deflection"][:3])
                got = mesh.point_data["displacement"][last_point]
                check(numpy.abs(got - expected).max() <= 1e-12 * numpy.abs(expected).max(),
                      f"portal case {dataset.get('name')}: link {name}: {got} against {expected}")
    if failures:
        return 1
    print("all VTK checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
