"""mkdocs hooks (mkdocs.yml, `hooks:`).

README.md holds the one table of test targets and their times (`.ci/run` and the people who
update the figures edit it there); docs/testing.md names it on a line ending in MARKER, which the
site replaces with the table itself.
"""
import pathlib
import re

from mkdocs.exceptions import PluginError

MARKER = "<!-- README.md: test targets -->"
TABLE = re.compile(r"<!-- test targets: start[^\n]*-->\s*\n(.*?)\n\s*<!-- test targets: end -->", re.S)


def on_page_markdown(markdown, page, config, files):
    if MARKER not in markdown:
        return markdown
    readme = pathlib.Path(config["config_file_path"]).parent / "README.md"
    found = TABLE.search(readme.read_text(encoding="utf-8"))
    if not found:
        raise PluginError(f"{readme}: no table between <!-- test targets: start --> and <!-- test targets: end -->")
    lines = markdown.split("\n")
    return "\n".join(found.group(1) if MARKER in line else line for line in lines)
