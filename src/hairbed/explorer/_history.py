"""The page's URL and the browser's history, kept in step with the view.

:class:`BrowserHistory` is an invisible Panel component (``JSComponent``: a few lines of
JavaScript sent with the page and compiled in the browser; no file from any other host). Its
``search`` parameter is the query string the browser's address bar shows, in both directions:

- the server sets it after every good update (:meth:`ExplorerPage.refresh
  <hairbed.explorer._page.ExplorerPage.refresh>`); the browser then writes it into the address
  bar. The first change after a quiet spell of :data:`SETTLE_MS` adds a history entry
  (``history.pushState``), the changes that follow it within :data:`SETTLE_MS` of each other
  replace that entry (``history.replaceState``): a slider drag is one entry, not one per step;
- Back and Forward (the browser's ``popstate``) set it from the browser; the server then
  applies the new query the way it applies a loaded URL (validated by the library, the view
  redrawn), so that the address bar and the picture agree again.

When the page loads, the address bar is rewritten (``replaceState``, no new entry) to the
query of the view on screen: the whole set of inputs, even where the link gave only some.
"""

from __future__ import annotations

import param
from panel.custom import JSComponent

__all__ = ["BrowserHistory", "SETTLE_MS"]

#: Quiet time [ms] after which a change of the view adds a history entry; changes closer
#: together (the steps of a slider drag) replace the entry of the first.
SETTLE_MS = 500

_ESM = """
// one popstate listener per page, whichever render of the view added it
let listener = null

export function render({ model }) {
  const settle = __SETTLE_MS__
  let last = -Infinity  // performance.now() of the last change of the address bar
  const here = () => window.location.search
  const go = (search, replace) => {
    const url = window.location.pathname + search + window.location.hash
    if (replace) {
      window.history.replaceState(window.history.state, "", url)
    } else {
      window.history.pushState(null, "", url)
    }
  }
  if (model.search !== "" && model.search !== here()) {
    go(model.search, true)  // the loaded link, written out whole: no new entry
  }
  model.on("search", () => {
    if (model.search === here()) {
      return  // the browser's own move (Back, Forward) coming back from the server
    }
    const now = performance.now()
    go(model.search, now - last < settle)
    last = now
  })
  if (listener !== null) {
    window.removeEventListener("popstate", listener)
  }
  listener = () => {
    last = performance.now()
    model.search = here()  // to the server, which shows the view of this URL
  }
  window.addEventListener("popstate", listener)
  model.on("remove", () => {
    if (listener !== null) {
      window.removeEventListener("popstate", listener)
      listener = null
    }
  })
}
""".replace("__SETTLE_MS__", str(SETTLE_MS))


class BrowserHistory(JSComponent):
    """The query string of the browser's address bar (see the module's description).

    Parameters
    ----------
    search : str
        The query string, '?' included ('' for none).
    """

    search = param.String(default="", doc="The address bar's query string, '?' included.")

    _esm = _ESM
