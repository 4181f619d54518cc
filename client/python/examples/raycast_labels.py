#!/usr/bin/env python3
"""Look at a semfuse map from Python, notebook style (run it whole, or cell by cell in an editor that
knows `# %%` cells): raycast the map from a camera, save the label image in the legend's colours,
and list what the view shows, by label.

    python3 client/python/examples/raycast_labels.py --pose ../shared/data/7scenes-redkitchen/frame-000000.pose.txt \\
        --intrinsics 640 480 585 585 320 240 --out view/

Without --pose it looks at the demo's synthetic room from a corner (deploy/demo.sh's first view).
"""
from __future__ import annotations

# %% Connect
import argparse
from pathlib import Path

import cv2
import numpy as np

import semfuse

# The demo's overview of the synthetic room (camera-to-world, rows of a 3x4 matrix).
DEMO_VIEW = [0.6114475, 0.4127809, -0.6750881, 2.2, 0.7912850, -0.3189671, 0.5216590, -1.7,
             0, -0.8531541, -0.5216590, 2.2]

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("--pose", nargs="+", default=[str(v) for v in DEMO_VIEW],
                    help="a 4x4 pose file (7-Scenes .pose.txt) or 12 / 16 numbers, camera-to-world, row-major")
parser.add_argument("--intrinsics", nargs=6, type=float, default=[640, 480, 525, 525, 319.5, 239.5],
                    metavar=("W", "H", "FX", "FY", "CX", "CY"))
parser.add_argument("--out", type=Path, default=Path("view"), help="folder for the images")
parser.add_argument("--domain-id", type=int, help="DDS domain (default: Cyclone's)")
parser.add_argument("--dds-profile", help="Cyclone DDS XML profile, e.g. deploy/dds/localhost.xml")
args = parser.parse_args()

map_client = semfuse.MapClient(participant=semfuse.Participant(args.domain_id, args.dds_profile), timeout=10)
legend = map_client.legend()
status = map_client.status()
print(f"map: {status.frames_integrated} frames fused, {status.allocated_voxels} voxels of "
      f"{100 * status.voxel_size:.0f} mm; legend '{legend.name}' with {len(legend)} labels")

# %% Choose the camera
if len(args.pose) == 1:
    pose = np.loadtxt(args.pose[0]).reshape(4, 4)
else:
    pose = np.eye(4)
    pose[: len(args.pose) // 4] = np.array([float(v) for v in args.pose]).reshape(-1, 4)
width, height, fx, fy, cx, cy = args.intrinsics
camera = semfuse.Intrinsics(int(width), int(height), fx, fy, cx, cy)

# %% Raycast: depth, labels and confidence as numpy arrays
view = map_client.raycast(pose, camera, layers=["depth", "labels", "confidence"])
labels, depth = view["labels"], view["depth"]
seen = depth > 0
print(f"view: {seen.mean():.0%} of the pixels see the map, depth {depth[seen].min():.2f} to "
      f"{depth[seen].max():.2f} m" if seen.any() else "view: the camera sees nothing of the map")

# %% Save the label image in the legend's colours (and the raw ids)
args.out.mkdir(parents=True, exist_ok=True)
cv2.imwrite(str(args.out / "labels.png"), cv2.cvtColor(legend.colorize(labels), cv2.COLOR_RGB2BGR))
cv2.imwrite(str(args.out / "labels_raw.png"), labels)
print(f"wrote {args.out / 'labels.png'} and labels_raw.png")

# %% What the view shows, by label
ids, counts = np.unique(labels[labels > 0], return_counts=True)
for label, count in sorted(zip(ids.tolist(), counts.tolist()), key=lambda pair: -pair[1]):
    mean_confidence = float(view["confidence"][labels == label].mean())
    print(f"  {legend.name_of(label) or label:>16}: {count / labels.size:6.1%} of the view, "
          f"mean score {mean_confidence:.1f}")
