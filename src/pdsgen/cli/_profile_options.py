"""The product commands' options, made from the option vocabulary and the missions' declarations.

A command's --help lists every option of every profile; silently ignoring one a profile has
no use for would let a user believe it took effect, so giving it is an error. Which options a
profile uses is its mission's declaration (`Mission.options`), read when the command runs:
a mission registered later needs no edit here, and no profile is named in cli/.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from typing import Any, TypeVar

import click
from click.core import ParameterSource

from ..errors import PdsgenError
from ..missions import DEFAULT_PROFILE, get_mission, mission_names
from ..products.options import DTM_OPTIONS, NOT_GIVEN, ORTHO_OPTIONS, OptionSpec, library_options, used_options
from ..results import CommandResult
from ._output import OUTPUT_OPTIONS

F = TypeVar("F", bound=Callable[..., Any])
R = TypeVar("R", bound=CommandResult)


def refuse_unused_options(ctx: click.Context, profile: str, used: Iterable[str]) -> None:
    """PdsgenError naming the first option given on the command line that `profile` does not use."""
    used = set(used)
    for param in ctx.command.params:
        if param.name in used or param.name in OUTPUT_OPTIONS or param.name == "profile" \
                or not isinstance(param, click.Option):
            continue
        if ctx.get_parameter_source(param.name) not in (ParameterSource.DEFAULT, None):
            flag = max(param.opts, key=len)
            raise PdsgenError(None, f"{flag} does not apply to --profile {profile}")


class UsedByProfile(Mapping[str, frozenset[str]]):
    """Profile name -> the click parameters its command accepts: the command's own (`structural`:
    OUTDIR, INPUT ...) and the vocabulary entries the profile's mission declares for `kind`.

    Read from the registry on each look-up, so a mission registered at run time is included."""

    def __init__(self, kind: str, vocabulary: Sequence[OptionSpec], structural: Iterable[str]) -> None:
        self.kind, self.vocabulary, self.structural = kind, vocabulary, frozenset(structural)

    def __getitem__(self, profile: str) -> frozenset[str]:
        if profile not in mission_names():
            raise KeyError(profile)
        specs = used_options(self.kind, get_mission(profile), self.vocabulary)
        return self.structural | {spec.param for spec in specs}

    def __iter__(self) -> Iterator[str]:
        return iter(mission_names())

    def __len__(self) -> int:
        return len(mission_names())

    def of(self, profile: str) -> frozenset[str]:
        """The parameters `profile` uses (an unknown profile: the default profile's)."""
        return self.get(profile) or self[DEFAULT_PROFILE]

    def library_options(self, params: Mapping[str, Any]) -> dict[str, Any]:
        """The library keywords (with their values) of the options the command's profile uses
        (products.options.library_options, which a batch job calls too)."""
        return library_options(self.kind, self.vocabulary, params)


class ProfileCommand(click.Command):
    """A product command that refuses, as it parses its command line, an option its --profile
    does not use: so a batch manifest's entry, which the command parses (`make_context`), is
    refused alike without batch/ asking cli/ for the check."""

    def __init__(self, *args: Any, used_by_profile: UsedByProfile, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.used_by_profile = used_by_profile

    def parse_args(self, ctx: click.Context, args: list[str]) -> list[str]:
        rest = super().parse_args(ctx, args)
        if not ctx.resilient_parsing:  # shell completion parses half a command line
            profile = ctx.params["profile"]
            refuse_unused_options(ctx, profile, self.used_by_profile.of(profile))
        return rest


def __getattr__(name: str) -> Any:
    """`_CLI_NAMES`: library keyword -> click parameter name, where they differ, in every command's
    vocabulary. Made when asked for: a DTM conversion does not import the mosaic's vocabulary."""
    if name != "_CLI_NAMES":
        raise AttributeError(name)
    from ..mosaic.options import MOSAIC_OPTIONS

    return {spec.library_keyword: spec.param for spec in (*DTM_OPTIONS, *ORTHO_OPTIONS, *MOSAIC_OPTIONS)
            if spec.library_keyword != spec.param}


class ProfileChoice(click.Choice):
    """--profile's choices: the missions registered when the command line is parsed, sorted."""

    def __init__(self) -> None:
        super().__init__(())

    @property
    def choices(self) -> tuple[str, ...]:
        return tuple(sorted(mission_names()))

    @choices.setter
    def choices(self, _value: Sequence[str]) -> None:
        pass


def profile_option(help_text: str, default: str | None = DEFAULT_PROFILE) -> Callable[[F], F]:
    """--profile, defaulting to the default profile (None: no default)."""
    if default is None:
        return click.option("--profile", type=ProfileChoice(), help=help_text)
    return click.option("--profile", type=ProfileChoice(), default=default, show_default=True, help=help_text)


def click_option(spec: OptionSpec) -> Callable[[F], F]:
    """The click option of one vocabulary entry."""
    attrs: dict[str, Any] = {"help": spec.help}
    if spec.choices is not None:
        attrs["type"] = click.Choice(spec.choices)
    elif spec.file:
        attrs["type"] = click.Path(dir_okay=False)
    elif spec.value_type is not None:
        attrs["type"] = spec.value_type
    if spec.is_flag:
        attrs["is_flag"] = True
    if spec.default is not NOT_GIVEN:
        attrs["default"] = spec.default
    if spec.show_default:
        attrs["show_default"] = True
    if spec.multiple:
        attrs["multiple"] = True
    if spec.nargs != 1:
        attrs["nargs"] = spec.nargs
    if spec.metavar is not None:
        attrs["metavar"] = spec.metavar
    if spec.required:
        attrs["required"] = True
    return click.option(f"--{spec.flag}", spec.param, **attrs)


def vocabulary_options(vocabulary: Sequence[OptionSpec]) -> Callable[[F], F]:
    """Every option of a command's vocabulary, in its order on --help."""
    def decorate(command: F) -> F:
        for spec in reversed(vocabulary):
            command = click_option(spec)(command)
        return command
    return decorate


# -- -o/--output: one flag name for "where the command writes", in every command ----------------------
# The commands once spelled it --outdir, --out or --output; the old spellings still work (scripts and
# shell histories use them) but --help and error messages show only -o/--output. The click parameter
# keeps its name (outdir, out, page), so a command's body, a batch job's parameters and a manifest's
# old keys are unchanged.

OUTPUT_FLAGS = ("-o", "--output")


class AliasedOption(click.Option):
    """An option whose older long names are accepted on the command line but not shown."""

    def __init__(self, *args: Any, hidden_aliases: Sequence[str] = (), **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.hidden_aliases = tuple(hidden_aliases)

    @contextmanager
    def _shown_names(self) -> Iterator[None]:
        """self.opts without the aliases, while click writes help or an error hint from them."""
        every = self.opts
        self.opts = [opt for opt in every if opt not in self.hidden_aliases]
        try:
            yield
        finally:
            self.opts = every

    def get_help_record(self, ctx: click.Context) -> tuple[str, str] | None:
        with self._shown_names():
            return super().get_help_record(ctx)

    def get_error_hint(self, ctx: click.Context | None) -> str:
        with self._shown_names():
            return super().get_error_hint(ctx)


def output_option(name: str, old_flag: str, **attrs: Any) -> Callable[[F], F]:
    """-o/--output with the click parameter `name`, still accepting `old_flag` (--outdir, --out).
    A directory is shown as OUTDIR, the word the commands' help uses for it ("... into OUTDIR")."""
    kind = attrs.get("type")
    if isinstance(kind, click.Path) and not kind.file_okay:
        attrs.setdefault("metavar", "OUTDIR")
    return click.option(*OUTPUT_FLAGS, old_flag, name, cls=AliasedOption, hidden_aliases=(old_flag,), **attrs)


def warned_in_cli_words(result: R) -> R:
    """A product's result with its warnings naming options as the command line spells them (a
    product made without identification keywords names the params file to give: --params)."""
    if result.warnings and dataclasses.is_dataclass(result):
        # `template`: `pdsgen params --template` (cli/params.py), the command a warning names
        options = {"template": "--template", **{spec.library_keyword: f"--{spec.flag}"
                                                 for spec in (*DTM_OPTIONS, *ORTHO_OPTIONS)}}
        warnings = tuple(_OWN_REFERENCE.sub(lambda m: _in_words(m, options), warning) for warning in result.warnings)
        return dataclasses.replace(result, warnings=warnings)
    return result


# `name` or `name='value'` (pdsgen.errors.param): the references a product's warnings make.
_OWN_REFERENCE = re.compile(r"`([a-z][a-z0-9_]*)(?:='([^'`]*)')?`")


def _in_words(match: re.Match[str], options: Mapping[str, str]) -> str:
    """One reference as the command line writes it (the products' vocabulary only: translating
    a product's warning loads no other command's, cli._messages.in_cli_words does for errors)."""
    option = options.get(match.group(1))
    if option is None:
        return match.group(0)
    return option if match.group(2) is None else f"{option} {match.group(2)}"
