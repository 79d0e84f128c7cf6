"""Render every figure and page the commands wrote, to look at them as a reader would.

    python validation/figures/render.py DIR [--page-width 1366]

Every SVG under DIR becomes a PNG beside it (cairosvg, `pip install cairosvg`); every index.html
becomes index-<width>.png, a screenshot at a laptop's width, when Chromium is installed (Debian:
`apt-get install chromium`). The machine checks are `cargo xtask check-figures DIR`; this is for
the eye. Not part of the build, the tests or CI.
"""

import argparse
import pathlib
import shutil
import subprocess
import sys
import tempfile


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dir", type=pathlib.Path)
    parser.add_argument("--page-width", type=int, default=1366)
    args = parser.parse_args()
    try:
        import cairosvg
    except ImportError:
        print("cairosvg is missing: pip install cairosvg", file=sys.stderr)
        return 1
    svgs = sorted(args.dir.rglob("*.svg"))
    for svg in svgs:
        cairosvg.svg2png(url=str(svg), write_to=str(svg.with_suffix(".png")))
    print(f"{len(svgs)} figure(s) rendered under {args.dir}")
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    pages = sorted(args.dir.rglob("index.html"))
    if pages and not browser:
        print("no Chromium: pages not rendered", file=sys.stderr)
        return 0
    for page in pages:
        shot = page.with_name(f"index-{args.page_width}.png")
        with tempfile.TemporaryDirectory() as profile:
            subprocess.run(
                [browser, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 f"--user-data-dir={profile}", "--hide-scrollbars",
                 f"--window-size={args.page_width},2400", f"--screenshot={shot}", page.resolve().as_uri()],
                check=True, capture_output=True, timeout=120,
            )
        print(f"{page} -> {shot}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
