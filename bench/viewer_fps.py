#!/usr/bin/env python3
"""Frames per second of `stiffmsa view` pages while orbiting, in headless Chromium (software
WebGL: SwiftShader on the CPU, no GPU), for bench/README.md.

    viewer_fps.py build/stiffmsa [FRAMES]

Writes the benchmark models (make_models.py: chains and frames of growing size) and their pages
into a temporary folder, opens each page in a 1280 × 800 window and times FRAMES renders of a
turning camera by requestAnimationFrame (the page's stiffmsaMeasureFps), after the time from
navigation to the first drawing. Prints one row per model."""
import pathlib
import subprocess
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests" / "browser"))
import chromium_pipe  # noqa: E402

# Example robots, then make_models.py's chains and frames.
MODELS = [("industrial-6axis",), ("gough-stewart-6ups",), ("chain", "100"), ("chain", "1000"), ("chain", "10000"),
          ("chain", "100000"), ("frame", "2", "2", "3"), ("frame", "5", "5", "10"), ("frame", "10", "10", "20")]


def main():
    cli = sys.argv[1]
    frames = int(sys.argv[2]) if len(sys.argv) > 2 else 120
    executable = chromium_pipe.find_chromium()
    if not executable:
        sys.exit("Chromium is not installed")
    with open("/proc/loadavg") as load:
        print(f"load average at the start: {load.read().split()[0]}")
    print(f"| model | links | page MB | open s | fps ({frames} frames) |")
    print("|---|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as temporary, chromium_pipe.Chromium(executable, timeout=600) as browser:
        folder = pathlib.Path(temporary)
        for spec in MODELS:
            name = "-".join(spec)
            model = folder / f"{name}.yaml"
            if len(spec) == 1:
                model = HERE.parent / "examples" / f"{name}.yaml"
            else:
                model.write_text(subprocess.run([sys.executable, str(HERE / "make_models.py"), *spec],
                                                capture_output=True, text=True, check=True).stdout)
            page_file = folder / f"{name}.html"
            subprocess.run([cli, "view", str(model), "-o", str(page_file)], check=True, capture_output=True)
            start = time.monotonic()
            page = chromium_pipe.Page(browser, page_file.as_uri(), 1280, 800)
            page.next_frames()
            opened = time.monotonic() - start
            links = page.evaluate("JSON.parse(document.getElementById('stiffmsa-data').textContent).links.names.length")
            measured = page.evaluate(f"stiffmsaMeasureFps({frames})", timeout=600)
            errors = page.errors()
            page.close()
            print(f"| {name} | {links} | {page_file.stat().st_size / 1e6:.1f} | {opened:.1f} | {measured['fps']:.1f} |"
                  + (f" errors: {errors}" if errors else ""))


if __name__ == "__main__":
    main()
