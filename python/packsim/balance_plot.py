"""``python -m packsim.balance_plot CSV PNG``: draws the table ``packsim balance-time --plot``
wrote as CSV (time to balance and peak board temperature against the resistor)."""
import sys

from .balance import _plot_csv

if __name__ == "__main__":
    sys.exit(_plot_csv())
