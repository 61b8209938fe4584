"""The benchmark for other harnesses: dataset rows (:mod:`.row_model`, :mod:`.rows`), the
Hugging Face dataset folder (:mod:`.dataset_export`). Import from the modules: this package's
face stays empty so that :mod:`.row_model` imports without the simulator."""
