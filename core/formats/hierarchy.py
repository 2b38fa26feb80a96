"""The HIERARCHY and MOTION header of BVH-like text files (BVH and GMR share it).

Parsing is a small recursive descent over tokens that remember their line and column;
every problem raises :class:`~core.errors.MotionFileError` naming what was expected.
Only the header is tokenised in Python; the frame lines are left to
:mod:`core.formats.frames`, which hands them to numpy.

Line endings are normalised first (CRLF, CR and LF, even mixed, each end one line).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from gmr_studio.core.errors import MotionFileError, quoted
from gmr_studio.core.formats.frames import MAX_ABS_VALUE, out_of_range, within_range
from gmr_studio.core.model.motion import check_joint_name

#: channel names as written in files, with what they drive: ("position"|"rotation", axis)
CHANNEL_NAMES = {f"{axis}{kind}": (kind, axis) for kind in ("position", "rotation") for axis in "XYZ"}
_CHANNEL_BY_LOWER = {name.lower(): name for name in CHANNEL_NAMES}
_TOKEN = re.compile(r"[{}]|[^\s{}]+")
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?\Z")


def normalise_newlines(data: bytes) -> bytes:
    """CRLF and lone CR become LF, so every line ends in exactly one LF."""
    if b"\r" not in data:
        return data
    return data.replace(b"\r\n", b"\n").replace(b"\r", b"\n")


@dataclass
class Token:
    text: str
    line: int
    column: int


@dataclass
class ParsedJoint:
    """One joint block as written: ``kind`` is 'ROOT', 'JOINT' or 'End Site'."""

    name: str
    kind: str
    parent: int
    line: int
    offset: tuple[float, float, float] | None = None
    channels: list[str] = field(default_factory=list)
    channel_tokens: list[Token] = field(default_factory=list)
    softlink: Token | None = None


@dataclass
class ParsedHeader:
    joints: list[ParsedJoint]
    comments: list[str]
    n_frames: int
    frames_token: Token
    frame_time: float
    data_offset: int  # byte offset of the first frame line in the normalised data
    data_line: int  # its 1-based line number


class _Tokens:
    """Tokens of the header, read line by line from the normalised bytes."""

    def __init__(self, data: bytes, path: str, comment_prefix: str | None) -> None:
        self.data = data
        self.path = path
        self.comment_prefix = comment_prefix
        self.pos = 0  # byte offset of the next unread line
        self.line = 0  # number of the last line read
        self.pending: list[Token] = []
        self.comments: list[str] = []

    def error(self, message: str, token: Token | None = None) -> MotionFileError:
        if token is None:
            return MotionFileError(self.path, message, self.line + 1, 1)
        return MotionFileError(self.path, message, token.line, token.column)

    def next_line_text(self) -> str | None:
        """The next raw line (decoded), or None at the end of the data."""
        if self.pos >= len(self.data):
            return None
        end = self.data.find(b"\n", self.pos)
        end = len(self.data) if end < 0 else end
        raw = self.data[self.pos : end]
        self.pos = end + 1
        self.line += 1
        try:
            return raw.decode("utf-8")
        except UnicodeDecodeError as exc:
            column = len(raw[: exc.start].decode("utf-8", "replace")) + 1
            raise MotionFileError(self.path, "bytes that are not UTF-8 text", self.line, column) from None

    def _fill(self) -> bool:
        while not self.pending:
            text = self.next_line_text()
            if text is None:
                return False
            stripped = text.lstrip()
            if self.comment_prefix and stripped.startswith(self.comment_prefix):
                self.comments.append(stripped[len(self.comment_prefix) :].strip())
                continue
            self.pending = [Token(m.group(), self.line, m.start() + 1) for m in _TOKEN.finditer(text)]
        return True

    def peek(self) -> Token | None:
        return self.pending[0] if self._fill() else None

    def take(self, expected: str) -> Token:
        """The next token; ``expected`` describes it for the error at end of file."""
        if not self._fill():
            raise self.error(f"unexpected end of file: expected {expected}")
        return self.pending.pop(0)

    def rest_of_line(self) -> list[Token]:
        """The tokens left on the current line (possibly none)."""
        out, self.pending = self.pending, []
        return out

    def expect(self, word: str, context: str = "") -> Token:
        token = self.take(f"'{word}'{context}")
        if token.text != word:
            raise self.error(f"expected '{word}'{context}, found {quoted(token.text)}", token)
        return token

    def number(self, what: str) -> float:
        token = self.take(what)
        if not _NUMBER.match(token.text):
            raise self.error(f"expected {what}, found {quoted(token.text)}", token)
        value = float(token.text)
        if not within_range(value):
            raise self.error(out_of_range(token.text), token)
        return value


def parse_header(data: bytes, path: str, dialect: str) -> ParsedHeader:
    """Parse everything up to the first frame line.

    ``dialect`` is 'bvh' or 'gmr'. GMR files start with a ``GMR <version>`` line, may hold
    ``#`` comment lines and ``SOFTLINK name`` in a joint block, and have no End Sites.
    """
    gmr = dialect == "gmr"
    tokens = _Tokens(data, path, "#" if gmr else None)
    if gmr:
        first = tokens.take("'GMR 1' on the first line")
        version = tokens.rest_of_line()
        if first.text != "GMR" or [t.text for t in version] != ["1"]:
            raise tokens.error("expected 'GMR 1' (format name and version) on the first line", first)
    tokens.expect("HIERARCHY")
    joints: list[ParsedJoint] = []
    names: dict[str, int] = {}
    while True:
        token = tokens.take("'ROOT' or 'MOTION'")
        if token.text == "MOTION":
            break
        if token.text != "ROOT":
            raise tokens.error(f"expected 'ROOT' or 'MOTION', found {quoted(token.text)}", token)
        _parse_joint(tokens, token, "ROOT", -1, joints, names, gmr)
    if not joints:
        raise tokens.error("the HIERARCHY has no ROOT joint")
    n_frames, frames_token = _parse_frames_line(tokens)
    frame_time = _parse_frame_time_line(tokens)
    return ParsedHeader(
        joints=joints,
        comments=tokens.comments,
        n_frames=n_frames,
        frames_token=frames_token,
        frame_time=frame_time,
        data_offset=tokens.pos,
        data_line=tokens.line + 1,
    )


def _parse_name(tokens: _Tokens, keyword: Token) -> tuple[str, Token]:
    words = []
    while tokens.pending and tokens.pending[0].text not in "{}":
        words.append(tokens.pending.pop(0))
    if not words:
        raise tokens.error(f"expected a joint name after '{keyword.text}'", keyword)
    name = " ".join(w.text for w in words)
    try:
        check_joint_name(name)
    except ValueError as exc:
        raise tokens.error(str(exc), words[0]) from None
    return name, words[0]


def _parse_joint(
    tokens: _Tokens,
    keyword: Token,
    kind: str,
    parent: int,
    joints: list[ParsedJoint],
    names: dict[str, int],
    gmr: bool,
) -> None:
    if kind == "End Site":
        base = joints[parent].name + "_End"
        name, n = base, 2
        while name in names:
            name, n = f"{base}{n}", n + 1
        name_token = keyword
    else:
        name, name_token = _parse_name(tokens, keyword)
        if name in names:
            first = joints[names[name]].line
            raise tokens.error(f"joint name '{name}' is used twice (first at line {first})", name_token)
    index = len(joints)
    joint = ParsedJoint(name=name, kind=kind, parent=parent, line=keyword.line)
    joints.append(joint)
    names[name] = index
    what = f" opening {kind} '{name}'" if kind != "End Site" else " opening the End Site"
    tokens.expect("{", what)
    while True:
        token = tokens.take(f"'}}' closing {kind} '{name}' (opened at line {keyword.line})")
        word = token.text
        if word == "}":
            break
        if word == "OFFSET":
            if joint.offset is not None:
                raise tokens.error(f"second OFFSET in '{name}'", token)
            joint.offset = tuple(tokens.number("a number for OFFSET") for _ in range(3))
        elif word == "CHANNELS" and kind != "End Site":
            _parse_channels(tokens, token, joint)
        elif word == "JOINT" and kind != "End Site":
            _parse_joint(tokens, token, "JOINT", index, joints, names, gmr)
        elif word == "End" and kind != "End Site" and not gmr:
            site = tokens.take("'Site' after 'End'")
            if site.text != "Site":
                raise tokens.error(f"expected 'Site' after 'End', found {quoted(site.text)}", site)
            _parse_joint(tokens, token, "End Site", index, joints, names, gmr)
        elif word == "SOFTLINK" and gmr:
            if joint.softlink is not None:
                raise tokens.error(f"second SOFTLINK in '{name}'", token)
            joint.softlink = tokens.take("the name of the soft-link parent after 'SOFTLINK'")
            rest = tokens.rest_of_line()
            if rest:
                joint.softlink = Token(
                    " ".join([joint.softlink.text] + [t.text for t in rest]),
                    joint.softlink.line,
                    joint.softlink.column,
                )
        else:
            allowed = (
                "OFFSET or '}'"
                if kind == "End Site"
                else ("OFFSET, CHANNELS, JOINT, SOFTLINK or '}'" if gmr else "OFFSET, CHANNELS, JOINT, End Site or '}'")
            )
            if word == "MOTION":
                raise tokens.error(
                    f"expected '}}' closing {kind} '{name}' (opened at line {keyword.line}) before MOTION", token
                )
            raise tokens.error(f"expected {allowed} in {kind} '{name}', found {quoted(word)}", token)
    if joint.offset is None:
        raise tokens.error(f"{kind} '{name}' (line {keyword.line}) has no OFFSET", token)
    if gmr and kind != "End Site" and not any(c.endswith("rotation") for c in joint.channels):
        raise tokens.error(f"GMR joint '{name}' (line {keyword.line}) needs rotation channels", token)


def _parse_channels(tokens: _Tokens, keyword: Token, joint: ParsedJoint) -> None:
    if joint.channel_tokens:
        raise tokens.error(f"second CHANNELS in '{joint.name}'", keyword)
    count_token = tokens.take("the number of channels")
    if not count_token.text.isdigit():
        raise tokens.error(f"expected the number of channels, found {quoted(count_token.text)}", count_token)
    count = int(count_token.text)
    if count > 6:
        raise tokens.error(f"a joint has at most 6 channels, not {count}", count_token)
    for _ in range(count):
        token = tokens.take(f"{count} channel names")
        name = _CHANNEL_BY_LOWER.get(token.text.lower())
        if name is None:
            raise tokens.error(
                f"unknown channel {quoted(token.text)}: expected one of {', '.join(CHANNEL_NAMES)}", token
            )
        if name in joint.channels:
            raise tokens.error(f"channel '{name}' appears twice in '{joint.name}'", token)
        joint.channels.append(name)
        joint.channel_tokens.append(token)


def _header_line(tokens: _Tokens, label: str, pattern: str) -> tuple[str, Token]:
    """The value after ``label`` on the next non-blank line (``label`` may be glued to it)."""
    rest = tokens.rest_of_line()
    if rest:  # MOTION followed by more text on its line
        raise tokens.error(f"expected a line break after MOTION, found {quoted(rest[0].text)}", rest[0])
    while True:
        text = tokens.next_line_text()
        if text is None:
            raise tokens.error(f"unexpected end of file: expected '{label}'")
        if text.strip():
            break
    match = re.match(pattern, text, re.IGNORECASE)
    if not match:
        column = len(text) - len(text.lstrip()) + 1
        found = text.strip().split()[0]
        raise MotionFileError(tokens.path, f"expected '{label}', found {quoted(found)}", tokens.line, column)
    return match.group(1), Token(match.group(1), tokens.line, match.start(1) + 1)


def _parse_frames_line(tokens: _Tokens) -> tuple[int, Token]:
    value, token = _header_line(tokens, "Frames: <count>", r"\s*Frames:\s*(\S*)\s*$")
    if not value.isdigit():
        raise tokens.error(f"expected a whole number of frames after 'Frames:', found {quoted(value)}", token)
    return int(value), token


def _parse_frame_time_line(tokens: _Tokens) -> float:
    value, token = _header_line(tokens, "Frame Time: <seconds>", r"\s*Frame\s+Time:\s*(\S*)\s*$")
    if not _NUMBER.match(value) or not 0 < float(value) <= MAX_ABS_VALUE:
        raise tokens.error(f"expected a positive number of seconds after 'Frame Time:', found {quoted(value)}", token)
    return float(value)
