#!/usr/bin/env bash
# The README's picture of the report: the top of a report page (by default the main job's,
# out/report/ from scripts/run_main.sh) as headless Chromium draws it at 0.6 scale, 768x1080
# pixels, reduced to 256 colours by pngquant to stay small.
# Usage: scripts/report_screenshot.sh [REPORT_DIR] [OUT_PNG]   (defaults: out/report docs/report.png)
set -euo pipefail
cd "$(dirname "$0")/.."
REPORT="${1:-out/report}"
PNG="${2:-docs/report.png}"
[ -f "$REPORT/index.html" ] || { echo "report_screenshot: $REPORT/index.html does not exist (scripts/run_main.sh writes out/report/)" >&2; exit 1; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --user-data-dir="$work/profile" \
  --force-device-scale-factor=0.6 --window-size=1280,1800 --screenshot="$work/page.png" \
  "file://$(cd "$REPORT" && pwd)/index.html" >/dev/null 2>&1
pngquant --force --speed 1 --output "$PNG" 256 "$work/page.png"
echo "report_screenshot: $PNG ($(stat -c %s "$PNG") bytes)"
