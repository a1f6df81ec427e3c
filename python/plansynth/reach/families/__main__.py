"""``python -m plansynth.reach.families DIR``: (re)write the example problem files."""

from plansynth.reach.families.example_files import main

if __name__ == "__main__":
    main()
