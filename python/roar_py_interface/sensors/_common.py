"""What the sensors' modules share: the serialisation scheme's short name, vector spaces, and JPEG frames
from a peer checked before they are decoded."""
import io

import numpy as np
from PIL import Image

from .. import spaces
from ..base import RoarPyRemoteSupportedSensorSerializationScheme, SerialisedDataError

_Scheme = RoarPyRemoteSupportedSensorSerializationScheme


def _vector_space(size: int = 3, low=-np.inf, high=np.inf) -> spaces.Box:
    return spaces.Box(low=low, high=high, shape=(size,), dtype=np.float32)


def _jpeg(image: Image.Image) -> bytes:
    out = io.BytesIO()
    image.save(out, format="JPEG")
    return out.getvalue()


MAX_IMAGE_PIXELS = 1 << 25  # a camera frame from a peer: 32 megapixels (CARLA's largest cameras are 4K)


def _from_jpeg(data: bytes) -> Image.Image:
    """A JPEG a peer sent, its size checked from its header before its pixels are decoded."""
    try:
        image = Image.open(io.BytesIO(data))
        width, height = image.size
        if width * height > MAX_IMAGE_PIXELS:
            raise SerialisedDataError(f"a camera frame of {width}x{height} is more than {MAX_IMAGE_PIXELS} pixels")
        image.load()
    except SerialisedDataError:
        raise
    except Image.DecompressionBombError as error:  # PIL's own limit, met before the size is ours to check
        raise SerialisedDataError(f"a camera frame of more than {MAX_IMAGE_PIXELS} pixels ({error})") from None
    except (OSError, ValueError) as error:
        raise SerialisedDataError(f"a camera frame that is no image ({type(error).__name__}: {error})") from None
    return image
