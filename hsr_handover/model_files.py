"""Where the bundled model files live (package data beside the code), for Drake and non-Drake
code alike."""

from pathlib import Path

MODELS_DIR = Path(__file__).resolve().parent / "models"
HSR_SDF = MODELS_DIR / "hsrb" / "hsrb.sdf"
