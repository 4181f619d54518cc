#!/usr/bin/env python3
"""A semantic segmenter in Python for a running semfuse server: OpenCV's dnn module runs the ADE20K
DeepLabV3 model on each frame's colour image and the labels (ADE20K class i = the server's ade20k
legend id i) go to the map with the network's softmax confidence.

    semfuse-server --legend ade20k &
    semfuse-camera --source 7scenes:../shared/data/7scenes-redkitchen --rate 5 &
    python3 client/python/examples/dnn_segmenter.py --every 2 --idle-exit 10

Any other network plugs in the same way: write a function from a semfuse.Frame to labels (and
optionally a confidence) and hand it to semfuse.Segmenter.
"""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import cv2
import numpy as np

import semfuse

ROOT = Path(__file__).resolve().parents[3]
DEFAULT_MODEL = Path(os.environ.get("SEMFUSE_SHARED", ROOT.parent / "shared")) / "models/ade20k_deeplabv3_mnv2_257_logits.pb"


class DeepLab:
    """DeepLabV3 (TensorFlow graph cut to logits): RGB resized to size x size, scaled to [-1, 1], NCHW."""

    def __init__(self, model: Path, input_size: int, output_scale: float) -> None:
        self.net = cv2.dnn.readNetFromTensorflow(str(model))
        self.input_size = input_size
        self.output_scale = output_scale

    def __call__(self, frame: semfuse.Frame) -> tuple[np.ndarray, np.ndarray]:
        if frame.color is None:
            raise ValueError("the frame has no colour image (camera with --color-encoding none?)")
        blob = cv2.dnn.blobFromImage(frame.color, scalefactor=1 / 127.5, size=(self.input_size, self.input_size),
                                     mean=(127.5, 127.5, 127.5), swapRB=False)  # the frame is RGB already
        self.net.setInput(blob)
        logits = self.net.forward()[0].transpose(1, 2, 0)  # classes x h x w -> h x w x classes
        # Labels at a fraction of the frame's size: the server upsamples them to the depth image.
        height, width = frame.depth.shape
        size = (max(1, round(width * self.output_scale)), max(1, round(height * self.output_scale)))
        logits = cv2.resize(logits, size, interpolation=cv2.INTER_LINEAR)
        labels = logits.argmax(axis=2).astype(np.uint16)
        best = logits.max(axis=2, keepdims=True)
        confidence = 1.0 / np.exp(logits - best).sum(axis=2)  # the softmax of the winning class
        return labels, confidence.astype(np.float32)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--model", type=Path, default=DEFAULT_MODEL, help="TensorFlow .pb of the ADE20K DeepLab")
    parser.add_argument("--input-size", type=int, default=257, help="network input side (257 or 513)")
    parser.add_argument("--output-scale", type=float, default=0.5, help="labels' size as a fraction of the frame's")
    parser.add_argument("--segmenter-id", default="python-deeplab")
    parser.add_argument("--camera-id", default="", help="only this camera's frames (default: all)")
    parser.add_argument("--every", type=int, default=1, help="segment every Nth frame")
    parser.add_argument("--delay", type=float, default=0.0, help="seconds to hold each result")
    parser.add_argument("--duration", type=float, help="stop after this many seconds")
    parser.add_argument("--idle-exit", type=float, help="stop after this many seconds without a frame")
    parser.add_argument("--domain-id", type=int, help="DDS domain (default: Cyclone's)")
    parser.add_argument("--dds-profile", help="Cyclone DDS XML profile, e.g. deploy/dds/localhost.xml")
    args = parser.parse_args()
    if not args.model.is_file():
        print(f"dnn_segmenter: no model at {args.model} (--model, or SEMFUSE_SHARED)", file=sys.stderr)
        return 2

    network = DeepLab(args.model, args.input_size, args.output_scale)
    participant = semfuse.Participant(args.domain_id, args.dds_profile)
    segmenter = semfuse.Segmenter(network, segmenter_id=args.segmenter_id, camera_id=args.camera_id,
                                  every=args.every, delay=args.delay, participant=participant)
    print(f"dnn_segmenter: {args.model.name} on DDS domain {participant.domain_id}; Ctrl-C stops", flush=True)
    try:
        with segmenter:
            segmenter.run(duration=args.duration, idle_exit=args.idle_exit)
    except KeyboardInterrupt:
        pass
    stats = segmenter.stats()
    print(f"dnn_segmenter: {stats.received} frames received, {stats.published} segmentations published, "
          f"{stats.skipped} skipped for newer frames, {stats.failed} failed; "
          f"{stats.mean_segment_ms:.0f} ms per frame", flush=True)
    return 0 if stats.failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
