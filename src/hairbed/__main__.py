"""``python -m hairbed``: the command line of :mod:`hairbed.cli`."""

from hairbed._command import run_and_exit

__all__: list[str] = []

if __name__ == "__main__":
    run_and_exit()
