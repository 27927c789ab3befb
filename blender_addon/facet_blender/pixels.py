"""Pixel layouts between the core and Blender: the core's images are float32 (h, w, 3) with the
top row first and its regions count rows down from the top; Blender's render results are RGBA
with the bottom row first, and its border counts pixels up from the bottom."""
import numpy as np


def to_blender_rect(img):
    """float32 (h, w, 3) top row first -> float32 (w*h, 4) RGBA, rows bottom to top (what
    RenderPass.rect.foreach_set takes in one call); an (h, w, 4) image (film transparency,
    holdouts: premultiplied colour and alpha, as Cycles' Combined) keeps its alpha."""
    h, w = img.shape[:2]
    rgba = np.empty((h, w, 4), np.float32)
    rgba[:, :, :3] = img[::-1, :, :3]
    rgba[:, :, 3] = img[::-1, :, 3] if img.shape[2] == 4 else 1.0
    return rgba.reshape(h * w, 4)


def border_rect(rd, width, height):
    """Render > Region (border): (x, y, w, h) in Blender's pixel coordinates (y up); the whole
    image without a border. Facet renders the region (bit for bit the pixels of the full
    render, render.h)."""
    if not rd.use_border:
        return 0, 0, width, height
    x0, x1 = round(rd.border_min_x * width), round(rd.border_max_x * width)
    y0, y1 = round(rd.border_min_y * height), round(rd.border_max_y * height)
    x0, y0 = max(0, min(x0, width - 1)), max(0, min(y0, height - 1))
    x1, y1 = max(x0 + 1, min(x1, width)), max(y0 + 1, min(y1, height))
    return x0, y0, x1 - x0, y1 - y0


def core_region(x, y, w, h, height):
    """A border (x, y, w, h), y up, as the core's region (x0, y0, x1, y1), y down."""
    return x, height - y - h, x + w, height - y
