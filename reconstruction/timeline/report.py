"""What v.histo.timeline tells the user: the merge, the conflicts, the snapshot."""

from ..core.messages import note, warning

#: conflicts named in the warning (all are in the report file)
NAMED = 5


def report(result, config, size, seconds):
    """The messages of a run (``size``: bytes written; ``seconds``: its time)."""
    out = []
    m = result.merge
    if m is not None:
        out.append(note("{} epochs ({}) merged: {} buildings, {} versions; per epoch: "
                        "{}".format(len(m.per_epoch), ", ".join(map(str, sorted(m.per_epoch))),
                                    m.buildings, m.versions, ", ".join(
                                        "{} in {}".format(n, y)
                                        for y, n in sorted(m.per_epoch.items())))))
        if result.register is not None:
            out.append(note("{} buildings still standing (in the register <{}>, {} ids)".format(
                m.standing, config.register, result.register)))
        if m.conflicts:
            named = list(m.conflicts.items())[:NAMED]
            out.append(warning("{} buildings where the maps and the register disagree (attribute "
                               "conflict){}: {}".format(
                                   len(m.conflicts), "" if len(m.conflicts) <= NAMED
                                   else ", the first {}".format(NAMED),
                                   "; ".join("<{}>: {}".format(k, v) for k, v in named))))
        if m.apart:
            named = list(m.apart.items())[:NAMED]
            out.append(warning(
                "{} ids name buildings in different places on different maps (their "
                "footprints do not overlap), each kept as a building of its own{}: {}".format(
                    len(m.apart), "" if len(m.apart) <= NAMED else ", the first {}".format(NAMED),
                    "; ".join("<{}> also as {}".format(k, ", ".join("<{}>".format(n) for n in v))
                              for k, v in named))))
    if result.snapshot is not None:
        out.append(note("Snapshot of {} (epochs {}): {} buildings".format(
            result.snapshot, ", ".join(map(str, result.years)), result.buildings)))
    out.append(note("'{}' written ({}, {:.2f} MB) in {:.1f} s".format(
        config.output, "CityJSONSeq" if config.format == "cityjsonseq" else "CityJSON 2.0",
        size / 1e6, seconds)))
    return out


def report_json(result, config):
    """The JSON report: the counts, every conflict and the options."""
    m = result.merge
    return {
        "years": list(result.years),
        "snapshot": result.snapshot,
        "buildings": result.buildings,
        "per_epoch": {str(y): n for y, n in sorted(m.per_epoch.items())} if m else None,
        "versions": m.versions if m else None,
        "standing": m.standing if m else None,
        "conflicts": dict(m.conflicts) if m else {},
        "apart": dict(m.apart) if m else {},
        "models": dict(zip(map(str, config.years), config.models)),
        "register": config.register,
    }


def shell_counts(result):
    """The key=value lines of -g."""
    m = result.merge
    lines = ["buildings={}".format(result.buildings)]
    if m is not None:
        lines += ["epochs={}".format(len(m.per_epoch)), "versions={}".format(m.versions),
                  "standing={}".format(m.standing), "conflicts={}".format(len(m.conflicts)),
                  "apart={}".format(len(m.apart))]
        lines += ["buildings_{}={}".format(y, n) for y, n in sorted(m.per_epoch.items())]
    if result.snapshot is not None:
        lines.append("snapshot={}".format(result.snapshot))
    return lines
