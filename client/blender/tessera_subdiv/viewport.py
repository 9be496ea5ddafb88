"""The active 3D viewport's view, for live mode's pixel accuracy: the view matrix, field of view
and size of the region Blender last drew, read off its RegionView3D, and that view as the
client's Camera in an object's frame."""
import math
from dataclasses import dataclass
from typing import Optional, Tuple

from mathutils import Matrix

from .request import TesseraError, camera_in_object_frame


@dataclass(frozen=True)
class ViewportView:
    """What a 3D viewport shows: world to view (Blender's view_matrix, 16 floats row by row), the
    vertical field of view, the region's size in pixels, perspective or orthographic."""
    view_matrix: Tuple[float, ...]
    fov_y_deg: float
    width: int
    height: int
    perspective: bool


def region_view(region, region_3d) -> ViewportView:
    """The view of a VIEW_3D area's WINDOW region. The vertical field of view is the projection's:
    window_matrix[1][1] = 1 / tan(fov_y / 2) (a lens shift or a camera view's offset moves the
    frustum, not the pixel size, and is left out)."""
    projection = region_3d.window_matrix
    return ViewportView(view_matrix=tuple(c for row in region_3d.view_matrix for c in row),
                        fov_y_deg=math.degrees(2.0 * math.atan(1.0 / projection[1][1])),
                        width=int(region.width), height=int(region.height),
                        perspective=bool(region_3d.is_perspective))


def active_viewport_view(window_manager) -> Optional[ViewportView]:
    """The largest 3D viewport among the open windows (a timer has no area of its own to ask);
    None when no window shows one."""
    best, best_pixels = None, 0
    for window in window_manager.windows:
        screen = window.screen
        for area in screen.areas if screen else ():
            if area.type != "VIEW_3D":
                continue
            region = next((r for r in area.regions if r.type == "WINDOW"), None)
            region_3d = area.spaces.active.region_3d
            if region is not None and region_3d is not None and region.width * region.height > best_pixels:
                best, best_pixels = region_view(region, region_3d), region.width * region.height
    return best


def viewport_camera(obj, view: ViewportView):
    """The viewport as the client's Camera in obj's frame (Y-up)."""
    if not view.perspective:
        raise TesseraError("pixel accuracy follows a perspective viewport; the active one is orthographic")
    rows = view.view_matrix
    view_to_world = Matrix([rows[0:4], rows[4:8], rows[8:12], rows[12:16]]).inverted()
    return camera_in_object_frame(obj, view_to_world, view.fov_y_deg, view.width, view.height)
