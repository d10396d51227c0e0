// placeholder: written by the model-file pass
