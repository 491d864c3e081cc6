"""The entries' old home, kept so their module names still import.

Each validated case now has its own folder of the repository checkout,
``validation/<case>/`` (see :mod:`seawall.validation`); its ``entry.py`` is
loaded under the name it had here, so ``seawall.validation.entries.dam_break``
is ``validation/dam-break/entry.py`` and ``from seawall.validation.entries
import solitary_runup`` keeps working. Importing this package loads every
entry (it needs the checkout, like ``seawall validate``).
"""

from .. import entry_modules

entry_modules()
