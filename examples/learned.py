"""The learned baseline as a controller: the policy trained with an evolution strategy on the
vector environment (docs/vector.md, "A learned baseline"), registered as "learned".

Enter it in the benchmark:  build/plumetrace benchmark --controller examples/learned.py
Run it once:                PYTHONPATH=build/python /usr/bin/python3 examples/learned.py
Its weights ship with the package (plumetrace/learn/learned.json); retrain them with
python3 -m plumetrace.learn.es.
"""

import plumetrace as pt
from plumetrace.learn import Learned

pt.register_controller("learned", Learned)


def main():
    for trial in range(3):
        r = pt.run("scenarios/lochmatter2008.toml", algorithm="learned", seed=1, trial=trial,
                   trace=False)
        print(f"trial {trial}: {r['outcome']:8s} in {r['time_s']:6.1f} s, path {r['d_t']:.1f} m")


if __name__ == "__main__":
    main()
