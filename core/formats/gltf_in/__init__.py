"""glTF 2.0 in (``.glb``, ``.gltf``): :func:`read_gltf` turns a skin and its animation into
a motion; :func:`gltf_contents` lists a file's skins and animations. See :mod:`.reader`."""

from gmr_studio.core.formats.gltf_in.contents import gltf_contents
from gmr_studio.core.formats.gltf_in.reader import read_gltf

__all__ = ["gltf_contents", "read_gltf"]
