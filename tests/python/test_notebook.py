"""docs/python_sweep.ipynb runs headless (nbclient, on the python3 kernel) without an error and
shows what it says it shows: the plot, the images, and an error falling with the samples."""

import re

import nbformat
from nbclient import NotebookClient

from conftest import SOURCE


def test_the_example_notebook_runs_and_its_error_falls_with_the_samples():
    path = SOURCE / "docs" / "python_sweep.ipynb"
    notebook = nbformat.read(path, as_version=4)
    NotebookClient(notebook, timeout=600, kernel_name="python3",
                   resources={"metadata": {"path": str(path.parent)}}).execute()
    outputs = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    images = [o for o in outputs if "data" in o and "image/png" in o["data"]]
    assert len(images) >= 3  # the reference, the plot and the last render
    text = "".join(o.get("text", "") for o in outputs if o.output_type == "stream")
    slope = float(re.search(r"slope (-?[0-9.]+)", text).group(1))
    assert -0.9 < slope < -0.35, text
