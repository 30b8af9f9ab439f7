"""Whole processes timed in turn: the medians docs/performance.md quotes.

    python3 benches/alternate.py N COMMAND ::: COMMAND [::: COMMAND …]

Each COMMAND is a program and its arguments (``VAR=value`` words before the
program set its environment); the commands run one after the other, N rounds,
their output discarded, and each one's fastest, quartiles and median wall time
are printed. Alternating is what makes two builds comparable on a shared
virtual machine whose speed drifts by a third within an hour, e.g.

    python3 benches/alternate.py 300 \\
        old/gecaro identify stanford --method position --data m5000s.csv --sigma 1e-5 ::: \\
        target/release/gecaro identify stanford --method position --data m5000s.csv --sigma 1e-5
"""

import os
import subprocess
import sys
import time


def command(words):
    environment = dict(os.environ)
    while words and "=" in words[0] and not words[0].startswith(("/", ".")):
        name, value = words[0].split("=", 1)
        environment[name] = value
        words = words[1:]
    if not words:
        sys.exit("a command without a program")
    return environment, words


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    rounds = int(sys.argv[1])
    commands, current = [], []
    for word in sys.argv[2:]:
        if word == ":::":
            commands.append(current)
            current = []
        else:
            current.append(word)
    commands.append(current)
    runs = [command(words) for words in commands]
    times = [[] for _ in runs]
    for _ in range(rounds):
        for (environment, words), taken in zip(runs, times):
            started = time.perf_counter()
            subprocess.run(
                words,
                env=environment,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
                check=False,
            )
            taken.append(time.perf_counter() - started)
    for words, taken in zip(commands, times):
        taken.sort()
        at = lambda share: taken[int(share * (len(taken) - 1))] * 1e3  # noqa: E731
        print(
            f"fastest {at(0):6.2f}  p25 {at(0.25):6.2f}  median {at(0.5):6.2f}  "
            f"p75 {at(0.75):6.2f} ms  {' '.join(words)}"
        )


if __name__ == "__main__":
    main()
