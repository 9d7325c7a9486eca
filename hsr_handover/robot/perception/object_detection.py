"""Object detection by colour on an RGB-D frame: colour segmentation in HSV, contours, bounding
boxes, and each box's 3-D centre from the depth image (paper section 4.3).

The graspable objects are saturated, distinctly coloured cups and boxes; the palette of those
colours is the detector's prior (its colour classes), not ground truth. A pixel belongs to a
colour class when its hue lies in a window around the class's hue and its saturation and value
are not far below the class's own; diffuse shading scales a colour's RGB, which keeps its hue
and saturation and lowers its value, so the windows hold across lit and shaded faces while the
person's skin, the brown table, grey clothes, the white/grey robot and the pale sky fall below
the saturation floor. One detection per connected blob of a class that is large enough.

Images follow `pinhole.PinholeCamera`'s conventions: pixel (u, v) is column u, row v, and depth
is metres along the optical axis (inf, NaN or <= 0 where there is no measurement).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import cv2
import numpy as np

from hsr_handover.interface.object_colors import OBJECT_COLORS
from hsr_handover.interface.pinhole import PinholeCamera, to_frame, valid_depth

OK = "ok"
_NO_CLASS = 255  # class-image value of pixels outside every colour window
_HUE_RANGE = 180  # OpenCV's 8-bit hue runs over 0..179, in units of 2 degrees
_MIN_PALETTE_SATURATION = 64  # of 255: the hue of a greyer colour is too unstable to classify by


@dataclasses.dataclass(frozen=True, eq=False)
class Detection:
    """One coloured blob: its box (u_min, v_min, u_max, v_max), inclusive pixel indices, the box's
    centre pixel (u, v), the 3-D centre in the world (NaN when the blob has no valid depth),
    the number of the blob's pixels and which pixels of the box they are (`blob`, bool, the
    box's shape; None when not known, as for detections made elsewhere). `label` is the
    colour name, with "#2", "#3", ... appended for the second, third, ... largest blob of a
    colour that shows more than once."""

    label: str
    color: str
    box: tuple[int, int, int, int]
    center_pixel: tuple[float, float]
    center: np.ndarray
    pixel_count: int
    blob: np.ndarray | None = dataclasses.field(default=None, repr=False)


@dataclasses.dataclass(frozen=True)
class DetectionResult:
    """The detections of one frame, in palette order and, within a colour, largest first.
    `status` is "ok" when there are detections, else a short reason why there are none."""

    detections: tuple[Detection, ...]
    status: str

    def seen(self, label: str) -> np.ndarray | None:
        """The centre (m, world) of the largest detection of `label` located in depth, None
        when there is none."""
        for detection in self.detections:
            if detection.label == label and np.all(np.isfinite(detection.center)):
                return np.asarray(detection.center, dtype=float)
        return None


@dataclasses.dataclass(frozen=True)
class DetectorSettings:
    """Colour windows and blob filtering.

    A colour class accepts hues within `max_hue_tolerance_deg` of its palette hue (narrowed to
    half the gap to the nearest other palette hue so that no two windows overlap), saturation
    at least `min_saturation_fraction` of the palette colour's and value at least
    `min_value_fraction` of it (shaded faces are dark but keep their hue). Masks are opened
    with an `opening_size` square to drop anti-aliased edges and speckle; blobs of fewer than
    `min_pixels` pixels are ignored. Blobs of a colour whose centres lie within
    `same_object_m` of each other are one object seen in parts (an arm or the image's edge
    across it): objects stand 15 cm or more apart, and a cup or box is 5-10 cm across.
    """

    min_pixels: int = 40
    max_hue_tolerance_deg: float = 20.0
    min_saturation_fraction: float = 0.65
    min_value_fraction: float = 0.1
    opening_size: int = 3
    same_object_m: float = 0.1


@dataclasses.dataclass(frozen=True)
class _ColorClasses:
    """Per-class lookup tables indexed by 8-bit hue (class index) or by class index (floors)."""

    names: tuple[str, ...]
    class_of_hue: np.ndarray  # (256,) uint8
    saturation_floor: np.ndarray  # (256,) uint8, the least saturation a class accepts
    value_floor: np.ndarray  # (256,) uint8, the least value a class accepts


def detect_objects(
    rgb: np.ndarray,
    depth: np.ndarray,
    camera: PinholeCamera,
    X_WC: np.ndarray,
    palette: Mapping[str, tuple[float, float, float]] = OBJECT_COLORS,
    settings: DetectorSettings = DetectorSettings(),  # noqa: B008 (frozen, so shared safely)
) -> DetectionResult:
    """Detect the palette-coloured objects in an RGB image (H, W, 3) uint8 with its aligned depth
    image (H, W) in metres, seen by `camera` (intrinsics for this H x W) at pose `X_WC` (4 x 4).

    Degraded frames (empty, no valid depth, nothing object-coloured) give no detections and a
    status saying why. Images whose size differs from each other or from `camera` raise
    ValueError: that is a wiring error, not a bad frame.
    """
    degraded = _degraded_input_reason(rgb, depth, camera, X_WC)
    if degraded is not None:
        return DetectionResult((), degraded)
    classes = _color_classes(palette, settings)
    class_image = _classify_pixels(rgb, classes)
    histogram = cv2.calcHist([class_image], [0], None, [256], [0, 256]).ravel()
    present = np.flatnonzero(histogram[: len(classes.names)])
    if present.size == 0:
        return DetectionResult((), "no object-coloured pixels")
    detections = [
        detection
        for index in present
        for detection in _detections_of_color(
            classes.names[index], class_image == index, depth, camera, X_WC, settings
        )
    ]
    if not detections:
        return DetectionResult((), f"no blob of at least {settings.min_pixels} pixels")
    return DetectionResult(tuple(detections), OK)


def check_palette(
    palette: Mapping[str, tuple[float, float, float]],
    settings: DetectorSettings = DetectorSettings(),  # noqa: B008 (frozen, so shared safely)
) -> None:
    """Raise ValueError when colour alone cannot tell the palette's colours apart (two share a
    hue, or one is too grey to have a stable hue), before any frame arrives."""
    _color_classes(palette, settings)


def _detections_of_color(
    color: str,
    mask: np.ndarray,
    depth: np.ndarray,
    camera: PinholeCamera,
    X_WC: np.ndarray,
    settings: DetectorSettings,
) -> list[Detection]:
    # Each object: the detection of its largest blob, and every blob that is a part of it.
    objects: list[tuple[Detection, list[tuple[tuple[int, int, int, int], np.ndarray]]]] = []
    for box, blob in _blobs(mask, settings):
        part = _detection(color, color, box, blob, depth, camera, X_WC)
        whole = next((whole for whole in objects if _near(part, whole[0], settings)), None)
        if whole is None:
            objects.append((part, [(box, blob)]))
        else:
            whole[1].append((box, blob))
    detections = []
    for rank, (largest, parts) in enumerate(objects, start=1):
        # Objects are told apart by colour; a repeated colour gets numbered, largest first.
        label = color if rank == 1 else f"{color}#{rank}"
        if len(parts) == 1:
            detections.append(dataclasses.replace(largest, label=label))
        else:
            box, blob = _joined(parts)
            detections.append(_detection(label, color, box, blob, depth, camera, X_WC))
    return detections


def _near(part: Detection, whole: Detection, settings: DetectorSettings) -> bool:
    """Whether `part` lies within `same_object_m` of `whole` (never with a NaN centre)."""
    return bool(np.linalg.norm(part.center - whole.center) <= settings.same_object_m)


def _joined(
    parts: list[tuple[tuple[int, int, int, int], np.ndarray]],
) -> tuple[tuple[int, int, int, int], np.ndarray]:
    """One box and blob mask holding every part's (box, blob mask in the box)."""
    boxes = np.array([box for box, _ in parts])
    u_min, v_min = boxes[:, :2].min(axis=0)
    u_max, v_max = boxes[:, 2:].max(axis=0)
    blob = np.zeros((v_max - v_min + 1, u_max - u_min + 1), bool)
    for (u, v, u_end, v_end), part in parts:
        blob[v - v_min : v_end - v_min + 1, u - u_min : u_end - u_min + 1] |= part
    return (int(u_min), int(v_min), int(u_max), int(v_max)), blob


def label_colour(label: str) -> str:
    """The colour a detection's label names: "purple#2", the second purple blob, is purple."""
    return label.partition("#")[0]


def _degraded_input_reason(
    rgb: np.ndarray, depth: np.ndarray, camera: PinholeCamera, X_WC: np.ndarray
) -> str | None:
    if rgb.size == 0 or depth.size == 0:
        return "empty image"
    if rgb.ndim != 3 or rgb.shape[2] != 3 or rgb.dtype != np.uint8:
        raise ValueError(f"rgb: expected an (H, W, 3) uint8 image, got {rgb.shape} {rgb.dtype}")
    if depth.shape != rgb.shape[:2] or depth.shape != (camera.height, camera.width):
        raise ValueError(
            f"image sizes differ: rgb {rgb.shape[:2]}, depth {depth.shape}, "
            f"camera {(camera.height, camera.width)} (rows, columns)"
        )
    if not np.all(np.isfinite(X_WC)):
        return "invalid camera pose"
    if not np.any(valid_depth(depth)):
        return "no valid depth"
    return None


def _color_classes(
    palette: Mapping[str, tuple[float, float, float]], settings: DetectorSettings
) -> _ColorClasses:
    names = tuple(palette)
    if not 0 < len(names) < _NO_CLASS:
        raise ValueError(f"palette: expected 1 to {_NO_CLASS - 1} colours, got {len(names)}")
    rgb = np.clip(np.round(np.array([palette[n] for n in names]) * 255), 0, 255)
    hsv = cv2.cvtColor(rgb.astype(np.uint8)[None], cv2.COLOR_RGB2HSV)[0].astype(int)
    hue, saturation, value = hsv.T
    grey = [n for n, s in zip(names, saturation, strict=True) if s < _MIN_PALETTE_SATURATION]
    if grey:
        raise ValueError(f"palette: {grey} are too grey to tell apart by hue")
    class_of_hue = np.full(256, _NO_CLASS, dtype=np.uint8)
    hues = np.arange(_HUE_RANGE)
    for index, tolerance in enumerate(_hue_tolerances(names, hue, settings)):
        gap = np.abs(hues - hue[index])
        class_of_hue[:_HUE_RANGE][np.minimum(gap, _HUE_RANGE - gap) <= tolerance] = index
    return _ColorClasses(
        names,
        class_of_hue,
        _floor_table(settings.min_saturation_fraction * saturation),
        _floor_table(settings.min_value_fraction * value),
    )


def _floor_table(floors: np.ndarray) -> np.ndarray:
    table = np.zeros(256, dtype=np.uint8)  # _NO_CLASS pixels stay unclassified whatever it says
    table[: len(floors)] = np.clip(np.ceil(floors), 0, 255)
    return table


def _hue_tolerances(
    names: tuple[str, ...], hue: np.ndarray, settings: DetectorSettings
) -> np.ndarray:
    """Half the circular gap to the nearest other hue, at most the maximum (8-bit hue units)."""
    gaps = np.abs(hue[:, None] - hue[None, :])
    gaps = np.minimum(gaps, _HUE_RANGE - gaps).astype(float)
    np.fill_diagonal(gaps, np.inf)
    nearest = gaps.min(axis=1)
    if np.any(nearest < 2):
        alike = [n for n, gap in zip(names, nearest, strict=True) if gap < 2]
        raise ValueError(f"palette: {alike} have the same hue; colour alone cannot tell them apart")
    # Strictly below half the gap, so a hue halfway between two classes belongs to neither.
    return np.minimum(settings.max_hue_tolerance_deg / 2.0, (nearest - 1) / 2.0)


def _classify_pixels(rgb: np.ndarray, classes: _ColorClasses) -> np.ndarray:
    """Class index of every pixel (H, W) uint8, _NO_CLASS outside every colour window."""
    hue, saturation, value = cv2.split(cv2.cvtColor(rgb, cv2.COLOR_RGB2HSV))
    class_image = cv2.LUT(hue, classes.class_of_hue)
    # OpenCV's element-wise ops, 255 for true: several times faster than numpy's on masks.
    accepted = cv2.bitwise_and(
        cv2.compare(saturation, cv2.LUT(class_image, classes.saturation_floor), cv2.CMP_GE),
        cv2.compare(value, cv2.LUT(class_image, classes.value_floor), cv2.CMP_GE),
    )
    cv2.bitwise_or(class_image, cv2.bitwise_not(accepted), dst=class_image)
    return class_image


def _blobs(
    mask: np.ndarray, settings: DetectorSettings
) -> list[tuple[tuple[int, int, int, int], np.ndarray]]:
    """(box, blob mask inside the box) of each large enough blob of a class, largest first."""
    kernel = np.ones((settings.opening_size, settings.opening_size), np.uint8)
    opened = cv2.morphologyEx(mask.view(np.uint8), cv2.MORPH_OPEN, kernel)
    contours, _ = cv2.findContours(opened, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    blobs = []
    for contour in contours:
        u, v, width, height = cv2.boundingRect(contour)
        # Fill the outline, then keep the class's own pixels: holes stay out of the count.
        blob = np.zeros((height, width), np.uint8)
        cv2.drawContours(blob, [contour], -1, 1, thickness=cv2.FILLED, offset=(-u, -v))
        blob &= opened[v : v + height, u : u + width]
        if cv2.countNonZero(blob) >= settings.min_pixels:
            blobs.append(((u, v, u + width - 1, v + height - 1), blob.astype(bool)))
    blobs.sort(key=lambda item: -np.count_nonzero(item[1]))
    return blobs


def _detection(
    label: str,
    color: str,
    box: tuple[int, int, int, int],
    blob: np.ndarray,
    depth: np.ndarray,
    camera: PinholeCamera,
    X_WC: np.ndarray,
) -> Detection:
    u_min, v_min, u_max, v_max = box
    center_pixel = ((u_min + u_max) / 2.0, (v_min + v_max) / 2.0)
    box_depth = depth[v_min : v_max + 1, u_min : u_max + 1]
    surface_depth = _surface_depth(box_depth, blob)
    visible_width = u_max - u_min + 1
    center = _object_center(camera, X_WC, center_pixel, surface_depth, visible_width)
    center.setflags(write=False)
    blob.setflags(write=False)
    return Detection(label, color, box, center_pixel, center, int(np.count_nonzero(blob)), blob)


def _surface_depth(box_depth: np.ndarray, blob: np.ndarray) -> float:
    """Depth of the object's front surface at the box centre (paper section 4.3): the mean over
    the centre pixel and its 8 neighbours, counting only pixels on the blob with valid depth.
    When the centre pixel is off the blob (a hollow or bent shape), the median depth of the
    blob's own pixels; NaN when the blob has no valid depth at all."""
    height, width = blob.shape
    row, column = (
        (height - 1) // 2,
        (width - 1) // 2,
    )  # nearest the box centre; halves round up-left
    window = np.s_[max(row - 1, 0) : row + 2, max(column - 1, 0) : column + 2]
    valid = valid_depth(box_depth) & blob
    if blob[row, column] and np.any(valid[window]):
        return float(np.mean(box_depth[window][valid[window]]))
    if np.any(valid):
        return float(np.median(box_depth[valid]))
    return float("nan")


def _object_center(
    camera: PinholeCamera,
    X_WC: np.ndarray,
    center_pixel: tuple[float, float],
    surface_depth: float,
    visible_width_pixels: int,
) -> np.ndarray:
    """The box centre pixel lifted to the front surface, then pushed along the viewing ray by
    half the object's visible width in metres. The push extends the paper's method (which
    grasps at the surface point): for a cylinder or a box seen face-on the axis lies one radius
    or half a side behind the surface, and the visible width measures that from the image."""
    surface_C = camera.deproject(np.array([center_pixel]), np.array([surface_depth]), np.eye(4))[0]
    half_width = visible_width_pixels * surface_depth / camera.fx / 2.0
    center_C = surface_C * (1.0 + half_width / np.linalg.norm(surface_C))
    return to_frame(X_WC, center_C)[0]
