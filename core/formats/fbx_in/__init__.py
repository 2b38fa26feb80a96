"""FBX in (``.fbx``, binary and ASCII): :func:`read_fbx` turns a file's skeleton and one of its
takes into a motion; :func:`fbx_contents` lists its takes. See :mod:`.reader`."""

from gmr_studio.core.formats.fbx_in.reader import fbx_contents, read_fbx

__all__ = ["fbx_contents", "read_fbx"]
