"""Cell clutter for many boxes on one large image: the summed-area tables make the per-box cost
O(1), so 10,000 boxes should cost about what one does (the image is read once either way).

Image 4096 × 4096 float32 noise; boxes of 4–32 pixels. Times best of several repeats; the last
line printed is one JSON object with the time for 10,000 boxes, for one, and their ratio, plus
the roofline (NumPy reading the image once and writing one array of its size).
"""

from __future__ import annotations

import json
import sys

import numpy as np

from _timing import best_of, roofline
from targetacq.physics.clutter import image_clutter

SIDE = int(sys.argv[1]) if len(sys.argv) > 1 else 4096
BOXES = 10_000


def main() -> None:
    rng = np.random.default_rng(3)
    image = rng.normal(1000.0, 30.0, (SIDE, SIDE)).astype(np.float32)
    w = rng.integers(4, 33, BOXES)
    h = rng.integers(4, 33, BOXES)
    boxes = np.column_stack([rng.integers(0, SIDE - w), rng.integers(0, SIDE - h), w, h])

    t_many = best_of(lambda: image_clutter(image, boxes), repeats=3)
    t_one = best_of(lambda: image_clutter(image, boxes[:1]), repeats=3)
    t_roof = best_of(roofline([image], outputs=1), repeats=3)
    result = {
        "benchmark": "clutter: image_clutter on a square image",
        "image_side": SIDE,
        "boxes": BOXES,
        "seconds_boxes": t_many,
        "seconds_one_box": t_one,
        "ratio_boxes_to_one": t_many / t_one,
        "boxes_per_second": BOXES / t_many,
        "roofline_seconds": t_roof,
        "roofline_ratio": t_one / t_roof,
    }
    print(
        f"{SIDE} x {SIDE} image: {BOXES:,} boxes in {t_many:.3f} s, one box in {t_one:.3f} s "
        f"(ratio {t_many / t_one:.2f}); one box is {t_one / t_roof:.1f} x the read-write roofline"
    )
    print(json.dumps(result))


if __name__ == "__main__":
    main()
