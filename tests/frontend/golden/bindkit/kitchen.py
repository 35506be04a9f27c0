"""A kitchen's bound functions, each with one mistake `stampc check` finds statically."""


def arg(action, name, convert):
    return convert(action.args[name])


def _follow(action):
    q = arg(action, "q", tuple)
    path = arg(action, "t", tuple) if "t" in action.args else ()
    return path, q


def pick(ctx, action):
    """Reads the held object as `o`."""
    o = arg(action, "o", str)
    _follow(action)
    return o


def wipe(ctx, action, extra):
    """Wants a third positional argument the engine never passes."""


def grasp(ctx, o, p):
    """Declared with two outputs (g, q); yields three values."""
    yield ("top", (0.0, 0.0), 1.0)


def approach(ctx, o, p):
    """Returns one tuple: the engine would iterate it value by value."""
    return ("top", (0.0, 0.0))


def reach(ctx, p, o):
    """Takes its inputs in the other order."""
    yield ((0.0, 0.0),)
