"""shapely 2's top-level geometry names (``from shapely import Polygon, Point``) on Debian's shapely 1.8,
which has them in ``shapely.geometry`` only. ROAR_PY_RL's environment imports them so; importing
roar_py_interface adds the names shapely lacks, the same classes, and changes nothing else."""
GEOMETRY_NAMES = ("Point", "LineString", "LinearRing", "Polygon", "MultiPoint", "MultiLineString", "MultiPolygon",
                  "GeometryCollection")


def install() -> bool:
    """Adds shapely.geometry's classes to shapely where it lacks them; True if it added any."""
    try:
        import shapely
        import shapely.geometry
    except ImportError:
        return False
    missing = [name for name in GEOMETRY_NAMES if not hasattr(shapely, name)]
    for name in missing:
        setattr(shapely, name, getattr(shapely.geometry, name))
    return bool(missing)
