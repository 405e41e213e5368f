import pathlib
import sys

# The example scripts import nothing from here; this only keeps pytest's rootdir stable.
sys.dont_write_bytecode = True
ROOT = pathlib.Path(__file__).resolve().parents[3]
