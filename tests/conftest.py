import sys
from pathlib import Path

# Let tests import the sibling helper module `quadrature`.
sys.path.insert(0, str(Path(__file__).parent))
