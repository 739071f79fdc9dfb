"""Old public names kept for one release: each warns with a ``DeprecationWarning`` naming its
replacement, then behaves exactly as the new name (issue 28: one spelling, American, as SciPy and
python-control spell it).

Examples
--------
>>> import warnings
>>> def optimize(x): return 2 * x
>>> __getattr__ = module_aliases("demo", {"optimise": ("demo.optimize", lambda: optimize)})
>>> with warnings.catch_warnings(record=True) as w:
...     warnings.simplefilter("always")
...     __getattr__("optimise")(2), w[0].category.__name__
(4, 'DeprecationWarning')
"""


from __future__ import annotations

import functools
import warnings
from collections.abc import Callable, Mapping
from typing import Any, TypeVar

from .errors import ArgumentTypeError

__all__ = ["renamed_attribute", "renamed_keywords", "module_aliases", "warn"]

F = TypeVar("F", bound=Callable[..., Any])


def warn(old: str, new: str, stacklevel: int = 3) -> None:
    """Warn that ``old`` is deprecated in favour of ``new`` (removed after one release)."""
    warnings.warn(f"{old} is deprecated and will be removed in the next release: use {new}",
                  DeprecationWarning, stacklevel=stacklevel)


def renamed_attribute(old: str, new: str, owner: str) -> property:
    """A read-only property under the old attribute name ``old`` that warns and returns
    ``self.<new>`` (for a method, the bound method)."""
    def get(self: Any) -> Any:
        warn(f"{owner}.{old}", f"{owner}.{new}")
        return getattr(self, new)

    get.__doc__ = f"Deprecated alias of :attr:`{new}` (one release)."
    return property(get, doc=get.__doc__)


def renamed_keywords(**old_to_new: str) -> Callable[[F], F]:
    """Accept old keyword names (``old=new``) with a warning, passing them on under the new name."""
    def decorate(func: F) -> F:
        @functools.wraps(func)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            for old, new in old_to_new.items():
                if old in kwargs:
                    warn(f"{func.__name__}({old}=...)", f"{func.__name__}({new}=...)")
                    if new in kwargs:
                        raise ArgumentTypeError(f"{func.__name__}: give {new}= (not both {old}= and {new}=)",
                                                argument=old, received=kwargs[old], expected=new)
                    kwargs[new] = kwargs.pop(old)
            return func(*args, **kwargs)

        return wrapper  # type: ignore[return-value]
    return decorate


def module_aliases(module: str, aliases: Mapping[str, tuple[str, Callable[[], Any]]]) -> Callable[[str], Any]:
    """A module ``__getattr__`` (PEP 562) serving old names: ``{old: (new name, getter)}``; the
    getter runs on first use, so the alias costs nothing at import."""
    def __getattr__(name: str) -> Any:
        if name in aliases:
            new, get = aliases[name]
            warn(f"{module}.{name}", new)
            return get()
        raise AttributeError(f"module {module!r} has no attribute {name!r}")

    return __getattr__
